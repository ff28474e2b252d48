//! From a [`Scene`] to the patch technique's inputs: the `[patches]` table ([`patch_settings`])
//! and the patch mesh with its textures ([`load_patches`]).
//!
//! Settings start from [`PatchSettings::default`], take the first `[[hair]]` entry's material
//! (its highlight constants, and its base color as the base texture's color), then every key of
//! `[patches]`. The mesh comes from one of three sources (`patches.source`):
//!
//! - `"obj"`: the hair-card OBJ file `patches.obj` (relative to the scene's folder), AO as stored
//!   in the file;
//! - `"strands"`: the scene's `[[hair]]` assets (merged) converted to cards
//!   (`tress_hair::patches::PatchMesh::from_strands`, `[patches.cards]`);
//! - `"generated"`: layered patches grown on the scene's generated head
//!   (`tress_hair::patches::generate_patches`, `[patches.generator]`);
//! - `"auto"` (default): `"obj"` when `patches.obj` is given, else `"strands"` when the scene has
//!   hair, else `"generated"`.
//!
//! AO is baked on load (`[patches.ao]`, `tress_hair::patches::bake_ao` against the patches and
//! the head) for generated and converted meshes, and not for OBJ files, which carry their own
//! (`ao.bake` overrides either way). Textures are procedural (`[patches.textures]`) unless PNG
//! files are named (`textures.base_png`, `alpha_png`, `spec_shift_png`, `spec_noise_png`).
//!
//! Every key with its default and meaning: [`crate::settings_reference`]`("patches")`
//! (`tress settings patches`, and the book's Patches chapter).

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{Affine3A, Vec3};
use serde::Deserialize;
use tress_hair::generate::Head;
use tress_hair::patches::{
    AoParams, AoSides, CardParams, HairTextures, PatchMesh, PatchParams, bake_ao, generate_patches,
};
use tress_scene::{HeadSource, Scene};

use super::{PatchSettings, RenderScheme, TextureSlot, load_texture_png};
use crate::scene_setup::PreparedScene;
use crate::{Material, RenderError, Shading};

/// `[patches.generator]`.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct GeneratorTable {
    layers: Option<u32>,
    patches_per_layer: Option<u32>,
    segments: Option<u32>,
    length: Option<f32>,
    inner_length: Option<f32>,
    width: Option<f32>,
    overlap: Option<f32>,
    tip_width: Option<f32>,
    layer_spacing: Option<f32>,
    waviness: Option<f32>,
    seed: Option<u64>,
}

/// `[patches.cards]`.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct CardTable {
    cards: Option<u32>,
    segments: Option<u32>,
    width_scale: Option<f32>,
    min_width: Option<f32>,
    iterations: Option<u32>,
    seed: Option<u64>,
}

/// `[patches.ao]`.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct AoTable {
    bake: Option<bool>,
    rays: Option<u32>,
    max_distance: Option<f32>,
    seed: Option<u64>,
    sides: Option<String>,
    patch_opacity: Option<f32>,
}

/// `[patches.textures]`.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct TextureTable {
    width: Option<u32>,
    height: Option<u32>,
    seed: Option<u64>,
    strands: Option<u32>,
    base_color: Option<Vec3>,
    contrast: Option<f32>,
    edge: Option<f32>,
    tip_start: Option<f32>,
    tip_fade: Option<f32>,
    shift_amplitude: Option<f32>,
    sparkle_threshold: Option<f32>,
    base_png: Option<PathBuf>,
    alpha_png: Option<PathBuf>,
    spec_shift_png: Option<PathBuf>,
    spec_noise_png: Option<PathBuf>,
}

/// The `[patches]` table: every key optional, unknown keys are errors naming key and line.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct PatchTable {
    scheme: Option<String>,
    shading: Option<String>,
    alpha_ref: Option<f32>,
    min_alpha: Option<f32>,
    ambient_occlusion: Option<bool>,
    mipmaps: Option<bool>,
    diffuse_color: Option<Vec3>,
    primary_color: Option<Vec3>,
    primary_exponent: Option<f32>,
    primary_shift: Option<f32>,
    secondary_color: Option<Vec3>,
    secondary_exponent: Option<f32>,
    secondary_shift: Option<f32>,
    source: Option<String>,
    obj: Option<PathBuf>,
    pub(super) generator: GeneratorTable,
    pub(super) cards: CardTable,
    pub(super) ao: AoTable,
    pub(super) textures: TextureTable,
}

fn table(scene: &Scene) -> Result<PatchTable, RenderError> {
    Ok(scene.technique_settings("patches")?)
}

macro_rules! set {
    ($dst:expr, $src:expr, $($f:ident),*) => { $( if let Some(v) = $src.$f { $dst.$f = v; } )* };
}

/// Patch settings from the scene: defaults, then `first_hair`, the first character's material
/// (`None` without hair; [`PreparedScene::first_hair`]), then `[patches]` (see the module docs).
/// Validated.
pub fn patch_settings(
    scene: &Scene,
    first_hair: Option<&Material>,
) -> Result<PatchSettings, RenderError> {
    let t = table(scene)?;
    let mut s = PatchSettings::default();
    if let Some(m) = first_hair {
        s.lighting = m.hair_lighting();
        s.textures.base_color = m.base_color;
        s.fiber = m.fiber;
    }
    if let Some(name) = &t.scheme {
        s.scheme = name.parse::<RenderScheme>()?;
    }
    if let Some(name) = &t.shading {
        s.shading = name.parse::<Shading>()?;
    }
    set!(s, t, alpha_ref, min_alpha, ambient_occlusion, mipmaps);
    set!(
        s.lighting,
        t,
        diffuse_color,
        primary_color,
        primary_exponent,
        primary_shift,
        secondary_color,
        secondary_exponent,
        secondary_shift
    );
    let tx = &t.textures;
    set!(
        s.textures,
        tx,
        width,
        height,
        seed,
        strands,
        base_color,
        contrast,
        edge,
        tip_start,
        tip_fade,
        shift_amplitude,
        sparkle_threshold
    );
    s.validate()?;
    Ok(s)
}

/// Where the patch mesh comes from (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum PatchSource {
    /// Layered patches on the generated head.
    Generated,
    /// A hair-card OBJ file (resolved path).
    Obj(PathBuf),
    /// The scene's hair assets converted to cards.
    Strands,
}

impl PatchSource {
    /// The setting's spelling.
    pub fn name(&self) -> &'static str {
        match self {
            PatchSource::Generated => "generated",
            PatchSource::Obj(_) => "obj",
            PatchSource::Strands => "strands",
        }
    }
}

/// The patch source the scene selects (see the module docs) for a scene with or without hair.
pub fn patch_source(scene: &Scene, has_hair: bool) -> Result<PatchSource, RenderError> {
    let t = table(scene)?;
    let obj = t.obj.as_deref().map(|p| scene.resolve(p));
    match (t.source.as_deref().unwrap_or("auto"), obj) {
        ("auto", Some(p)) | ("obj", Some(p)) => Ok(PatchSource::Obj(p)),
        ("obj", None) => Err(RenderError::Invalid(
            "patches.source = \"obj\" needs patches.obj".into(),
        )),
        ("auto", None) if has_hair => Ok(PatchSource::Strands),
        ("auto", None) | ("generated", _) => Ok(PatchSource::Generated),
        ("strands", _) if !has_hair => Err(RenderError::Invalid(
            "patches.source = \"strands\" needs a [[hair]] entry".into(),
        )),
        ("strands", _) => Ok(PatchSource::Strands),
        (other, _) => Err(RenderError::Invalid(format!(
            "unknown patches.source `{other}` (expected auto, generated, obj or strands)"
        ))),
    }
}

/// A scene's patch mesh and textures, ready to upload.
#[derive(Clone, Debug)]
pub struct PatchScene {
    /// The mesh (AO baked when asked).
    pub mesh: PatchMesh,
    /// The four textures (procedural, or read from the PNG files named in the scene).
    pub textures: HairTextures,
    /// Whether any texture came from a file.
    pub textures_from_files: bool,
    /// The point patches are sorted around: the head centre (the mesh's centre without head).
    pub sort_center: Vec3,
    /// Where the mesh came from.
    pub source: PatchSource,
    /// Seconds the AO bake took, when it ran.
    pub ao_bake_seconds: Option<f64>,
}

/// The generated-head parameters of `[patches.generator]` around `head`.
pub(super) fn generator_params(t: &GeneratorTable, head: Head) -> PatchParams {
    let mut p = PatchParams {
        head,
        ..PatchParams::default()
    };
    set!(
        p,
        t,
        layers,
        patches_per_layer,
        segments,
        length,
        inner_length,
        width,
        overlap,
        tip_width,
        layer_spacing,
        waviness,
        seed
    );
    p
}

pub(super) fn card_params(t: &CardTable) -> CardParams {
    let mut p = CardParams::default();
    set!(
        p,
        t,
        cards,
        segments,
        width_scale,
        min_width,
        iterations,
        seed
    );
    p
}

/// AO bake settings of `[patches.ao]` (the bake switch is read by [`load_patches`]).
pub(super) fn ao_params(t: &AoTable) -> Result<AoParams, RenderError> {
    let mut p = AoParams::default();
    set!(p, t, rays, max_distance, seed, patch_opacity);
    if let Some(s) = &t.sides {
        p.sides = parse_sides(s)?;
    }
    p.validate()
        .map_err(|e| RenderError::setting("patches.ao", e))?;
    Ok(p)
}

/// `"max"`, `"mean"` or `"front"` ([`AoSides`]).
pub fn parse_sides(s: &str) -> Result<AoSides, RenderError> {
    match s {
        "max" => Ok(AoSides::Max),
        "mean" => Ok(AoSides::Mean),
        "front" => Ok(AoSides::Front),
        _ => Err(RenderError::Invalid(format!(
            "unknown AO sides `{s}` (expected max, mean or front)"
        ))),
    }
}

/// Build the scene's patch mesh (generate, read or convert; bake AO) and textures. `prepared` is
/// the scene loaded with [`PreparedScene::load`] (its hair and head are used, not reloaded).
pub fn load_patches(scene: &Scene, prepared: &PreparedScene) -> Result<PatchScene, RenderError> {
    let t = table(scene)?;
    let settings = patch_settings(scene, prepared.first_hair())?;
    let source = patch_source(scene, prepared.first_hair().is_some())?;
    let head_center = match scene.head_source() {
        HeadSource::Generated(g) => Some(g.center()),
        _ => prepared.head.as_ref().map(|h| h.bounding_sphere().0),
    };
    let mut mesh = match &source {
        PatchSource::Obj(path) => PatchMesh::read_obj(path)?,
        PatchSource::Generated => {
            // Cards grow on the generated head where it is placed (the default head without
            // one).
            let (head, placement) = match scene.head_source() {
                HeadSource::Generated(g) => (g.head, g.placement),
                _ => (Head::default(), Affine3A::IDENTITY),
            };
            let mut mesh = generate_patches(&generator_params(&t.generator, head))?;
            mesh.transform(placement);
            mesh
        }
        PatchSource::Strands => {
            let hair = prepared.hair().ok_or_else(|| {
                RenderError::Invalid(
                    "patches.source = \"strands\" but the scene has no hair".into(),
                )
            })?;
            PatchMesh::from_strands(&hair, &card_params(&t.cards))?
        }
    };
    let bake = t.ao.bake.unwrap_or(!matches!(source, PatchSource::Obj(_)));
    let ao = ao_params(&t.ao)?;
    let ao_bake_seconds = if bake {
        let head = prepared.head.as_ref();
        let start = Instant::now();
        bake_ao(&mut mesh, head, &ao)?;
        Some(start.elapsed().as_secs_f64())
    } else {
        None
    };
    let mut textures = HairTextures::generate(&settings.textures)
        .map_err(|e| RenderError::setting("patches.textures", e))?;
    let mut textures_from_files = false;
    let files: [(TextureSlot, &Option<PathBuf>); 4] = [
        (TextureSlot::Base, &t.textures.base_png),
        (TextureSlot::Alpha, &t.textures.alpha_png),
        (TextureSlot::SpecShift, &t.textures.spec_shift_png),
        (TextureSlot::SpecNoise, &t.textures.spec_noise_png),
    ];
    for (slot, path) in files {
        if let Some(p) = path {
            *slot.of_mut(&mut textures) = load_texture_png(scene.resolve(p), slot)?;
            textures_from_files = true;
        }
    }
    let sort_center = head_center.unwrap_or_else(|| super::default_sort_center(&mesh));
    Ok(PatchScene {
        mesh,
        textures,
        textures_from_files,
        sort_center,
        source,
        ao_bake_seconds,
    })
}

/// Whether a path names a patch OBJ file (by extension).
pub fn is_obj(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first hair entry's material, as the session prepares it.
    fn first(scene: &Scene) -> Option<crate::Material> {
        let m = &scene.hair.first()?.material;
        Some(crate::scene_setup::hair_material(m).unwrap())
    }

    #[test]
    fn settings_take_material_then_table_and_reject_unknown_keys() {
        let text = "[[hair]]\ngenerator = { style = \"straight\", strands = 10 }\n\
                    [hair.material]\nprimary_shift = -0.2\nbase_color = [0.5, 0.4, 0.3]\n\
                    [patches]\nsecondary_shift = 0.3\nscheme = \"3-pass\"\n\
                    textures = { seed = 7 }\n";
        let mut scene = Scene::from_str(text, ".").unwrap();
        let s = patch_settings(&scene, first(&scene).as_ref()).unwrap();
        assert_eq!(s.lighting.primary_shift, -0.2);
        assert_eq!(s.lighting.secondary_shift, 0.3);
        assert_eq!(s.scheme, RenderScheme::ThreePass);
        assert_eq!(s.textures.seed, 7);
        assert_eq!(s.textures.base_color, Vec3::new(0.5, 0.4, 0.3));
        scene.apply_override("patches.primary_shift=0.05").unwrap();
        scene.apply_override("patches.alpha_ref=0.5").unwrap();
        let s = patch_settings(&scene, first(&scene).as_ref()).unwrap();
        assert_eq!((s.lighting.primary_shift, s.alpha_ref), (0.05, 0.5));

        let bad = Scene::from_str("\n[patches]\nshift = 1.0\n", ".").unwrap();
        let e = patch_settings(&bad, first(&bad).as_ref())
            .unwrap_err()
            .to_string();
        assert!(e.contains("shift") && e.contains("line 3"), "{e}");
        let bad = Scene::from_str("[patches]\nscheme = \"5-pass\"\n", ".").unwrap();
        assert!(patch_settings(&bad, first(&bad).as_ref()).is_err());
        let bad = Scene::from_str("[patches]\nalpha_ref = 2.0\n", ".").unwrap();
        assert!(
            patch_settings(&bad, first(&bad).as_ref())
                .unwrap_err()
                .to_string()
                .contains("alpha_ref")
        );
    }

    #[test]
    fn marschner_shading_takes_the_materials_fibre() {
        let text = "[[hair]]\ngenerator = { style = \"straight\", strands = 10 }\n\
                    [hair.material]\neumelanin = 0.2\nbeta_m = 0.4\n\
                    [patches]\nshading = \"marschner\"\n";
        let mut scene = Scene::from_str(text, ".").unwrap();
        let s = patch_settings(&scene, first(&scene).as_ref()).unwrap();
        assert_eq!(s.shading, Shading::Marschner);
        assert_eq!(s.fiber, scene.hair[0].material.fiber().unwrap());
        assert_eq!(s.fiber.beta_m, 0.4);
        assert_eq!(s.params().shading, 1);
        assert_eq!(PatchSettings::default().shading, Shading::Scheuermann);
        scene
            .apply_override("patches.shading=\"kajiya-kay\"")
            .unwrap();
        let e = patch_settings(&scene, first(&scene).as_ref())
            .unwrap_err()
            .to_string();
        assert!(e.contains("patches.shading"), "{e}");
        scene.apply_override("patches.shading=\"phong\"").unwrap();
        assert!(patch_settings(&scene, first(&scene).as_ref()).is_err());
    }

    #[test]
    fn sources_follow_the_table_and_the_scene() {
        let s = Scene::from_str("", ".").unwrap();
        assert_eq!(
            patch_source(&s, !s.hair.is_empty()).unwrap(),
            PatchSource::Generated
        );
        let s = Scene::from_str("[patches]\nobj = \"cards.obj\"\n", "dir").unwrap();
        assert_eq!(
            patch_source(&s, !s.hair.is_empty()).unwrap(),
            PatchSource::Obj(Path::new("dir").join("cards.obj"))
        );
        let hair = "[[hair]]\ngenerator = { style = \"straight\", strands = 10 }\n";
        let s = Scene::from_str(hair, ".").unwrap();
        assert_eq!(
            patch_source(&s, !s.hair.is_empty()).unwrap(),
            PatchSource::Strands
        );
        let s =
            Scene::from_str(&format!("{hair}[patches]\nsource = \"generated\"\n"), ".").unwrap();
        assert_eq!(
            patch_source(&s, !s.hair.is_empty()).unwrap(),
            PatchSource::Generated
        );
        for bad in ["source = \"obj\"", "source = \"strands\"", "source = \"x\""] {
            let s = Scene::from_str(&format!("[patches]\n{bad}\n"), ".").unwrap();
            assert!(patch_source(&s, !s.hair.is_empty()).is_err(), "{bad}");
        }
    }

    #[test]
    fn generated_cards_move_with_the_generated_head() {
        let text = "[[hair]]\ngenerator = { style = \"straight\", strands = 10 }\n\
                    [patches]\nsource = \"generated\"\n\
                    generator = { layers = 2, patches_per_layer = 6, segments = 3 }\n\
                    ao = { rays = 2 }\ntextures = { width = 8, height = 8, strands = 2 }\n";
        let moved = text.replace(
            "strands = 10 }\n",
            "strands = 10 }\ntransform = { translate = [1.0, 2.0, -3.0], rotate_deg = [30.0, 0.0, 10.0], scale = 0.5 }\n",
        );
        let load = |t: &str| {
            let scene = Scene::from_str(t, ".").unwrap();
            let prepared = PreparedScene::load(&scene).unwrap();
            let HeadSource::Generated(g) = scene.head_source() else {
                panic!("generated head expected")
            };
            (load_patches(&scene, &prepared).unwrap(), g)
        };
        let (rest, _) = load(text);
        let (placed, head) = load(&moved);
        assert_eq!(placed.source, PatchSource::Generated);
        assert_eq!(rest.mesh.positions().len(), placed.mesh.positions().len());
        for (a, b) in rest.mesh.positions().iter().zip(placed.mesh.positions()) {
            assert!(head.placement.transform_point3(*a).distance(*b) < 1e-4);
        }
        for (a, b) in rest.mesh.normals().iter().zip(placed.mesh.normals()) {
            let turned = head.placement.transform_vector3(*a).normalize();
            assert!(turned.distance(*b) < 1e-4);
        }
        assert!(placed.sort_center.distance(head.center()) < 1e-5);
    }

    #[test]
    fn generated_source_loads_with_ao_and_sorts_around_the_head() {
        let text = "[patches]\ngenerator = { layers = 2, patches_per_layer = 8, segments = 3 }\n\
                    ao = { rays = 4 }\ntextures = { width = 16, height = 16, strands = 4 }\n";
        let scene = Scene::from_str(text, ".").unwrap();
        let prepared = PreparedScene::load(&scene).unwrap();
        let p = load_patches(&scene, &prepared).unwrap();
        assert_eq!(p.source, PatchSource::Generated);
        assert_eq!(p.mesh.component_count(), 16);
        assert!(p.ao_bake_seconds.is_some());
        assert!(p.mesh.ao().iter().any(|&a| a < 1.0));
        let HeadSource::Generated(head) = scene.head_source() else {
            panic!("generated head expected");
        };
        assert_eq!(p.sort_center, head.center());
        assert_eq!(p.textures.base.width, 16);
        assert!(!p.textures_from_files);
    }
}
