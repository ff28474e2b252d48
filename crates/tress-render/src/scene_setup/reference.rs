//! What each key of `[strands]`, `[volume]` and `[hybrid]` means, with its default from
//! [`StrandSettings::default`], [`VolumeSettings::default`] and [`HybridSettings::default`]
//! (the scene reference, [`crate::settings_doc`]). The order is the book's.

use crate::settings_doc::{SettingDoc, doc};
use crate::{HybridSettings, StrandSettings, VolumeSettings};

/// The `[strands]` keys.
pub(crate) fn strands() -> Vec<SettingDoc> {
    let d = StrandSettings::default();
    vec![
        doc(
            "width_px",
            d.width_px,
            "ribbon width in pixels (the paper's constant line width)",
        ),
        doc("alpha", d.alpha, "strand opacity"),
        doc(
            "shading",
            d.shading.name(),
            "or `\"scheuermann\"` (two shifted highlights), or `\"marschner\"` (physically based, \
             see [Physically based strands](scenes.md#physically-based-strands-shading--marschner))",
        ),
        doc(
            "multiple_scattering",
            d.multiple_scattering,
            "`shading = \"marschner\"`: add the light scattered through other strands (dual \
             scattering's forward and backward terms) to each strand's R, TT and TRT; `false` \
             is single scattering only, the reference tracer's `trace.bounces = 0`",
        ),
        doc(
            "coverage",
            d.coverage,
            "multiply alpha by the §3.2 line coverage",
        ),
        doc(
            "thickness_fade",
            d.thickness_fade.name(),
            "`\"tip\"`: alpha × thickness / the asset's thickest vertex (tapered tips fade); \
             `\"projected\"`: physical sub-pixel coverage; `\"off\"`",
        ),
        doc(
            "oit",
            d.oit.name(),
            "order-independent transparency: `\"ppll\"` (the paper's per-pixel linked lists and \
             k-buffer), `\"shortcut\"` (bounded memory, never drops a fragment), `\"auto\"`: the \
             PPLL while its grown pool holds the frame and its k-buffer sorts at least a quarter \
             of the fragments, ShortCut otherwise (see below)",
        ),
        doc(
            "k",
            d.k,
            "PPLL: fragments per pixel blended in sorted order (k-buffer), the rest \
             order-independently",
        ),
        doc(
            "ppll_nodes_per_pixel",
            d.ppll_nodes_per_pixel,
            "initial PPLL node pool; it grows after a frame that dropped fragments",
        ),
        doc(
            "ppll_max_mib",
            d.ppll_max_bytes as f64 / (1u64 << 20) as f64,
            "cap of the node pool in MiB (spread over up to 4 storage bindings; lavapipe allows \
             128 MiB each)",
        ),
        doc(
            "shortcut_k",
            d.shortcut_k,
            "ShortCut: nearest depths kept per pixel (1–16); the `k - 1` nearer fragments are \
             shaded and blended in order, the k-th opens the tail",
        ),
        doc("shadows", d.shadows, "approximated deep shadow maps"),
        doc(
            "shadow_map_size",
            d.shadow_map_size,
            "shadow map edge in texels",
        ),
        doc(
            "shadow_r",
            d.shadow_r,
            "ADSM strand spacing `r` in `(1 - alpha)^(d r)`",
        ),
        doc("shadow_alpha", d.shadow_alpha, "ADSM `alpha`"),
        doc("pcf_radius", d.pcf_radius, "PCF kernel radius (1 = 3x3)"),
        doc(
            "shadow_bias",
            d.shadow_bias,
            "shadow depth bias (world units)",
        ),
        doc(
            "shadow_width_px",
            d.shadow_width_px,
            "strand width in the shadow map (texels): 1-texel lines at 1 or less, ribbons above",
        ),
        doc(
            "shadow_mode",
            d.shadow_mode.name(),
            "`\"volume\"`: shadows counted through the hair volume instead of ADSM's `d r` (no \
             shadow maps)",
        ),
        doc(
            "ao",
            d.ao,
            "multiply by the hair volume's local ambient occlusion",
        ),
    ]
}

/// The `[volume]` keys.
pub(crate) fn volume() -> Vec<SettingDoc> {
    let d = VolumeSettings::default();
    vec![
        doc(
            "resolution",
            d.resolution,
            "voxels per axis (cubic voxels over the hair's box; each counter buffer must fit the \
             storage-binding limit, the highlight sums' 8 bytes a voxel too: ≤ 256 on lavapipe); \
             with `screen_resolution`, the most a character gets",
        ),
        doc(
            "screen_resolution",
            d.screen_resolution,
            "size each voxelized character's grid by its size on screen: `voxels_per_px` voxels \
             a pixel across its bounding sphere, up to the next of 32, 48, 64, 96, 128, 192, 256, \
             384, 512, 768, 1024 and clamped to `min_resolution..=resolution` (a far character \
             costs kilobytes; a character with ambient occlusion on, `volume.ao` or `strands.ao`, \
             keeps `resolution`: the AO radius is in world units); `false`: every character at \
             `resolution`, the paper's fixed grid",
        ),
        doc(
            "voxels_per_px",
            d.voxels_per_px,
            "voxels across a character per pixel of its size on screen (`screen_resolution`; at \
             1 the far fur's volume scores FLIP 0.112 against its strands, at 2 0.058 as a fixed \
             grid)",
        ),
        doc(
            "min_resolution",
            d.min_resolution,
            "the fewest voxels per axis a character's grid gets under `screen_resolution`",
        ),
        doc(
            "voxelize",
            crate::volume::voxelize_mode_name(d.voxelize),
            "`\"segments\"`: each segment sampled at voxel frequency (no gaps, no filter); \
             `\"vertices\"`: the paper's one count per vertex plus a box reconstruction filter",
        ),
        doc(
            "reconstruction_radius",
            d.reconstruction_radius,
            "the vertices mode's filter radius in voxels (0–3)",
        ),
        doc(
            "max_strands_per_voxel",
            d.max_strands_per_voxel,
            "counter capacity (the paper's 8-bit counter); samples beyond are dropped and counted",
        ),
        doc(
            "steps",
            d.steps,
            "raymarching steps across the box diagonal",
        ),
        doc(
            "opacity",
            d.opacity.name(),
            "how the strands along an eye ray make the hair opaque: `\"strands\"`, as the strand \
             rasterizer's lines (every strand met is a line of the strands' `width_px`, `alpha` \
             and coverage, as long as its length seen across the ray, so the transmittance is \
             `exp(-Σ lines over the pixel × the line's optical width)` and the surface comes \
             nearer the outside farther away, as the strands' composite does); `\"iso\"`, the \
             paper's fixed count (`iso` below) at every distance",
        ),
        doc(
            "iso",
            d.iso,
            "`opacity = \"iso\"`: strands along a ray to a solid surface, each weighed by its tip \
             fade: the hair's transmittance falls as `256^(-strands / iso)` (1/256 at the \
             surface; a ray that never gets there has the fake-transparency opacity \
             `1 - transmittance`). 48 reaches as deep into the hair as the strands' composite at \
             the fur and ponytail scenes' own distance",
        ),
        doc(
            "highlights",
            d.highlights.name(),
            "where Kajiya-Kay's highlights come from: `\"strands\"`, the strands' own, integrated \
             per voxel by the voxelizer for the frame's view and each light (the mean of their \
             narrow lobes; the highlights sit where the strands have them); `\"mean_tangent\"`, \
             the paper's lobe of the voxels' mean tangent, widened by their spread (Toksvig). \
             Scheuermann and Marschner shading use the mean tangent",
        ),
        doc(
            "shade_samples",
            d.shade_samples,
            "points shaded per pixel (1–8), at the middles of equal shares of the composite's \
             weight along the ray; 1 shades where half the weight is reached (the paper shades \
             one point, on the surface). Each point costs its shadow marches: the bear's raymarch \
             at 640×360 takes 149 / 198 / 250–290 ms at 1 / 2 / 4 on lavapipe, hair FLIP against \
             the strands 0.200 / 0.175 / 0.167",
        ),
        doc(
            "skip_empty",
            d.skip_empty,
            "jump over empty 8³ blocks (same image, faster; off is the paper)",
        ),
        doc("shadows", d.shadows, "volume shadows"),
        doc(
            "occlusion",
            d.occlusion.name(),
            "how shadows and AO count the strands in the way: `\"adsm\"`, ADSM's model with the \
             strands' `shadow_r`, `shadow_alpha` and `shadow_bias`: shadows are the expectation \
             of ADSM's `(1 - alpha)^(r·(d - bias))` over where the first strand seen from the \
             light lies (a march step holds a strand of a shadow-map line with probability \
             `1 - exp(-density · step · width)`), AO `r` strands per world unit of path inside \
             the hair, so the volume darkens as the rasterizer does; `\"strands\"`, the strands \
             the march passes times `strand_width / voxel` with `shadow_alpha` (far lighter than \
             ADSM on fur)",
        ),
        doc(
            "shadow_alpha",
            d.shadow_alpha,
            "volume shadows: strand opacity (`occlusion = \"strands\"`)",
        ),
        doc(
            "shadow_step",
            d.shadow_step,
            "volume shadows: march step (voxels)",
        ),
        doc(
            "shadow_offset",
            d.shadow_offset,
            "volume shadows: march start (voxels)",
        ),
        doc(
            "strand_width",
            d.strand_width,
            "`occlusion = \"strands\"`: effective strand width (world units), the share \
             `strand_width / voxel` of the strands a shadow or AO ray passes that are in its way",
        ),
        doc(
            "ao",
            d.ao,
            "local ambient occlusion. Off by default like `strands.ao`: turn both on together, or \
             the volume is darker than the strands",
        ),
        doc(
            "ao_radius",
            d.ao_radius,
            "local AO: ball radius (world units)",
        ),
        doc("ao_samples", d.ao_samples, "local AO: samples"),
        doc("ao_intensity", d.ao_intensity, "local AO: strength"),
        doc(
            "ao_texel",
            d.ao_texel,
            "voxels a texel of the local AO texture baked after each voxelization while `ao` or \
             `strands.ao` reads it: every shaded point then reads AO with one filtered lookup \
             instead of `ao_samples` density samples. 1 bakes every voxel (4 bytes a voxel), 2 \
             every other one (an eighth of the bake and its memory, coarser AO), 0 evaluates the \
             samples at every shaded point (the paper's)",
        ),
        doc(
            "budget_mib",
            d.budget_mib,
            "GPU memory the volumes of a frame may take: the shared counters and each \
             character's own volume (see [Several characters]\
             (scenes.md#several-characters-hair-technique-and-technique--auto)); a character \
             whose volume would not fit is drawn as strands, with a warning and `fallback` in \
             `--json`'s `objects`",
        ),
    ]
}

/// The `[hybrid]` keys.
pub(crate) fn hybrid() -> Vec<SettingDoc> {
    let d = HybridSettings::default();
    vec![
        doc(
            "lod",
            d.lod,
            "fixed blend factor, 0 strands … 1 volume; absent: from the camera distance \
             between `near` and `far`",
        ),
        doc(
            "near",
            d.near,
            "eye distance (world units) where the blend from strands starts",
        ),
        doc(
            "far",
            d.far,
            "eye distance (world units) where the blend ends in the volume",
        ),
        doc(
            "transition",
            d.transition.name(),
            "`\"alpha\"` or `\"dither\"` (4×4 Bayer); a hybrid character among several always \
             dithers (see [Several characters]\
             (scenes.md#several-characters-hair-technique-and-technique--auto))",
        ),
        doc(
            "auto_near_px",
            d.auto_near_px,
            "`technique = \"auto\"`: a character whose bounding sphere is at least \
             `auto_near_px` pixels across is drawn as strands (`f = 1 - smoothstep(far, near, \
             size)` between)",
        ),
        doc(
            "auto_far_px",
            d.auto_far_px,
            "`technique = \"auto\"`: a character whose bounding sphere is at most `auto_far_px` \
             pixels across is drawn as the volume, the hybrid's blend between",
        ),
        doc(
            "budget_ms",
            d.budget_ms,
            "`technique = \"auto\"`, several characters: GPU milliseconds a frame may take; \
             nearest first, each character keeps its choice by size while it fits beside the \
             cheapest the farther ones can be drawn, else takes the cheaper renderer that fits \
             (strands before the volume), by costs measured on this device from the frames' \
             GPU timestamps; absent: no budget",
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::super::{HybridTable, StrandTable, VolumeTable};
    use super::super::{hybrid_settings, strand_settings, volume_settings};
    use super::*;
    use crate::settings_doc::introspect::{assert_same_keys, fields, flatten};
    use tress_scene::Scene;

    fn one_key(table: &str, d: &SettingDoc) -> Option<Scene> {
        let v = d.default.as_ref()?;
        Some(Scene::from_str(&format!("[{table}]\n{} = {v}\n", d.key), ".").unwrap())
    }

    #[test]
    fn documented_keys_are_the_tables_keys() {
        assert_same_keys(
            "strands",
            &strands(),
            &flatten(fields::<StrandTable>(), &[]),
        );
        assert_same_keys("volume", &volume(), &flatten(fields::<VolumeTable>(), &[]));
        assert_same_keys("hybrid", &hybrid(), &flatten(fields::<HybridTable>(), &[]));
    }

    #[test]
    fn documented_defaults_read_back_as_the_defaults() {
        for d in strands() {
            let scene = one_key("strands", &d).expect("every strand key has a default");
            let s = strand_settings(&scene).unwrap();
            assert_eq!(s, StrandSettings::default(), "strands.{}", d.key);
        }
        for d in volume() {
            let scene = one_key("volume", &d).expect("every volume key has a default");
            let s = volume_settings(&scene).unwrap();
            assert_eq!(s, VolumeSettings::default(), "volume.{}", d.key);
        }
        for d in hybrid() {
            let Some(scene) = one_key("hybrid", &d) else {
                // Absent by default (their meanings say what absence does).
                assert!(["lod", "budget_ms"].contains(&d.key), "{}", d.key);
                continue;
            };
            let s = hybrid_settings(&scene).unwrap();
            assert_eq!(s, HybridSettings::default(), "hybrid.{}", d.key);
        }
    }
}
