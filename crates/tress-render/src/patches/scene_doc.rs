//! What each key of `[patches]` means, with its default from [`PatchSettings::default`] and the
//! generator's, cards', AO bake's and textures' own defaults (the scene reference,
//! [`crate::settings_doc`]). Nested tables' keys are dotted (`generator.layers`).

use tress_hair::patches::{AoParams, AoSides, CardParams, PatchParams};

use super::PatchSettings;
use crate::settings_doc::{Absent, SettingDoc, doc};

/// The setting's spelling of `sides` (as [`super::scene::parse_sides`] reads it).
fn sides_name(sides: AoSides) -> &'static str {
    match sides {
        AoSides::Max => "max",
        AoSides::Mean => "mean",
        AoSides::Front => "front",
    }
}

/// The `[patches]` keys.
pub(crate) fn patches() -> Vec<SettingDoc> {
    let d = PatchSettings::default();
    let (l, tx) = (&d.lighting, &d.textures);
    let (g, c, ao) = (
        PatchParams::default(),
        CardParams::default(),
        AoParams::default(),
    );
    let scheme = d.scheme.to_string();
    vec![
        doc(
            "scheme",
            scheme.as_str(),
            "the slides' `\"4-pass\"` or `\"3-pass\"` scheme",
        ),
        doc(
            "shading",
            d.shading.name(),
            "or `\"marschner\"`: the `[hair.material]` fibre's lobes",
        ),
        doc(
            "alpha_ref",
            d.alpha_ref,
            "alpha test: alpha ≥ `alpha_ref` is opaque",
        ),
        doc(
            "min_alpha",
            d.min_alpha,
            "> 0: the last pass drops alpha below it (an option, see below)",
        ),
        doc(
            "ambient_occlusion",
            d.ambient_occlusion,
            "multiply by the mesh's baked AO",
        ),
        doc("mipmaps", d.mipmaps, "build mip chains for the textures"),
        doc(
            "diffuse_color",
            l.diffuse_color,
            "`diffuseColor`: multiplies the diffuse term",
        ),
        doc(
            "primary_color",
            l.primary_color,
            "`specularColor1`: the primary highlight's color",
        ),
        doc(
            "primary_exponent",
            l.primary_exponent,
            "`specExp1`: the primary highlight's exponent",
        ),
        doc(
            "primary_shift",
            l.primary_shift,
            "`primaryShift`: the primary highlight's tangent shift (negative: towards the tip)",
        ),
        doc(
            "secondary_color",
            l.secondary_color,
            "`specularColor2`: the secondary highlight's color",
        ),
        doc(
            "secondary_exponent",
            l.secondary_exponent,
            "`specExp2`: the secondary highlight's exponent",
        ),
        doc(
            "secondary_shift",
            l.secondary_shift,
            "`secondaryShift`: the secondary highlight's tangent shift (positive: towards the root)",
        ),
        doc(
            "source",
            "auto",
            "where the mesh comes from: `\"generated\"`, `\"obj\"`, `\"strands\"`; `\"auto\"` is \
             `\"obj\"` when `obj` is given, else `\"strands\"` when the scene has hair, else \
             `\"generated\"`",
        ),
        doc(
            "obj",
            Absent,
            "a hair-card OBJ file, relative to the scene's folder",
        ),
        doc("generator.layers", g.layers, "generated patches: layers"),
        doc(
            "generator.patches_per_layer",
            g.patches_per_layer,
            "patches around each layer",
        ),
        doc("generator.segments", g.segments, "quads along each strip"),
        doc(
            "generator.length",
            g.length,
            "the outer layer's strip length (world units)",
        ),
        doc(
            "generator.inner_length",
            g.inner_length,
            "the inner layer's length, a share of `length`",
        ),
        doc("generator.width", g.width, "widest strip (world units)"),
        doc(
            "generator.overlap",
            g.overlap,
            "how much wider strips are than the gaps between their centres",
        ),
        doc(
            "generator.tip_width",
            g.tip_width,
            "strip width at the tip, a share of its width",
        ),
        doc(
            "generator.layer_spacing",
            g.layer_spacing,
            "distance between layers, and of the inner layer from the scalp (world units)",
        ),
        doc(
            "generator.waviness",
            g.waviness,
            "largest random turn of a strip per unit of length (radians)",
        ),
        doc("generator.seed", g.seed, "random seed"),
        doc(
            "cards.cards",
            c.cards,
            "strands converted to cards: cards (k-means groups)",
        ),
        doc("cards.segments", c.segments, "quads along each card"),
        doc(
            "cards.width_scale",
            c.width_scale,
            "card width in standard deviations of the group's spread, times 2",
        ),
        doc(
            "cards.min_width",
            c.min_width,
            "smallest card width (world units)",
        ),
        doc("cards.iterations", c.iterations, "k-means rounds"),
        doc("cards.seed", c.seed, "seed of the k-means start"),
        doc(
            "ao.bake",
            Absent,
            "bake AO on load; absent: for generated and converted meshes, not for OBJ files \
             (which carry their own)",
        ),
        doc(
            "ao.rays",
            ao.rays,
            "AO bake: rays per hemisphere and vertex",
        ),
        doc(
            "ao.max_distance",
            ao.max_distance,
            "occluders farther than this do not count (world units)",
        ),
        doc("ao.seed", ao.seed, "seed of the ray directions"),
        doc(
            "ao.sides",
            sides_name(ao.sides),
            "which hemispheres count: `\"max\"` (the more open), `\"mean\"`, `\"front\"` (around \
             the normal)",
        ),
        doc(
            "ao.patch_opacity",
            ao.patch_opacity,
            "how much light a patch a ray crosses stops (1: opaque, as the head)",
        ),
        doc(
            "textures.width",
            tx.width,
            "procedural textures: texels across a patch",
        ),
        doc("textures.height", tx.height, "texels along a patch"),
        doc("textures.seed", tx.seed, "seed of all four textures"),
        doc("textures.strands", tx.strands, "strands across a patch"),
        doc(
            "textures.base_color",
            tx.base_color,
            "base color, linear RGB (the first `[[hair]]` material's `base_color` when there is \
             one)",
        ),
        doc(
            "textures.contrast",
            tx.contrast,
            "how dark the base's darkest streaks get",
        ),
        doc(
            "textures.edge",
            tx.edge,
            "share of the patch width on either side where strands thin out",
        ),
        doc(
            "textures.tip_start",
            tx.tip_start,
            "shortest strand, a share of the patch length",
        ),
        doc(
            "textures.tip_fade",
            tx.tip_fade,
            "length of a tip's fade, a share of the patch length",
        ),
        doc(
            "textures.shift_amplitude",
            tx.shift_amplitude,
            "amplitude of the specular shift around 0.5",
        ),
        doc(
            "textures.sparkle_threshold",
            tx.sparkle_threshold,
            "noise level under which the sparkle mask is 0",
        ),
        doc(
            "textures.base_png",
            Absent,
            "a PNG file for the base texture instead of the procedural one",
        ),
        doc(
            "textures.alpha_png",
            Absent,
            "a PNG file for the alpha texture",
        ),
        doc(
            "textures.spec_shift_png",
            Absent,
            "a PNG file for the specular shift texture",
        ),
        doc(
            "textures.spec_noise_png",
            Absent,
            "a PNG file for the specular noise texture",
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::super::scene::{
        AoTable, CardTable, GeneratorTable, PatchTable, TextureTable, ao_params, card_params,
        generator_params, patch_settings, patch_source,
    };
    use super::*;
    use crate::settings_doc::introspect::{assert_same_keys, fields, flatten};
    use tress_hair::generate::Head;
    use tress_scene::Scene;

    #[test]
    fn documented_keys_are_the_tables_keys() {
        let accepted = flatten(
            fields::<PatchTable>(),
            &[
                ("generator", fields::<GeneratorTable>()),
                ("cards", fields::<CardTable>()),
                ("ao", fields::<AoTable>()),
                ("textures", fields::<TextureTable>()),
            ],
        );
        assert_same_keys("patches", &patches(), &accepted);
    }

    #[test]
    fn documented_defaults_read_back_as_the_defaults() {
        let parts = |scene: &Scene| {
            let t: PatchTable = scene.technique_settings("patches").unwrap();
            format!(
                "{:?} {:?} {:?} {:?} {:?}",
                patch_settings(scene, None).unwrap(),
                generator_params(&t.generator, Head::default()),
                card_params(&t.cards),
                ao_params(&t.ao).unwrap(),
                (patch_source(scene, true), patch_source(scene, false)),
            )
        };
        let defaults = parts(&Scene::from_str("", ".").unwrap());
        for d in patches() {
            let Some(v) = &d.default else { continue };
            let scene = Scene::from_str(&format!("[patches]\n{} = {v}\n", d.key), ".").unwrap();
            assert_eq!(parts(&scene), defaults, "patches.{}", d.key);
        }
    }
}
