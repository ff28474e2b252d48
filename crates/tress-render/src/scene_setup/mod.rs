//! From a [`tress_scene::Scene`] to what a frame needs: hair, head mesh, lights, material, camera
//! and technique settings. The CLI, the benchmarks and the viewer all go through here, so a
//! scene renders the same everywhere.
//!
//! Each `[[hair]]` entry is a head of hair of its own ([`PreparedHair`]: its asset, material and
//! technique), so a scene can hold several characters; the strand renderer draws them in one
//! frame ([`crate::HairObject`]). Patches and SATF draw every entry merged into one asset
//! ([`PreparedScene::hair`]) with the first entry's material.

use std::borrow::Cow;
use std::path::Path;

use glam::Vec3;
use serde::Deserialize;
use tress_hair::{Aabb, HairAsset};
use tress_scene::{HeadSource, Scene, TechniqueKind};

mod framing;
pub(crate) mod reference;

pub use framing::{
    FRONT_VIEW, SIDE_VIEW, frame_bounds, framing_direction, projected_area, scale_world_defaults,
    unit_scale,
};

use crate::strands::ThicknessFade;
use crate::{Camera, DirectionalLight, Material, RenderError, Shading, StrandSettings, TriMesh};
use crate::{HybridSettings, ShadowMode, Transition, VolumeSettings};

/// One `[[hair]]` entry, resolved: a head of hair the strand renderer draws as an object of its
/// own.
#[derive(Clone, Debug)]
pub struct PreparedHair {
    /// The entry's strands (files merged or generated, followed, subset and transformed).
    pub asset: HairAsset,
    /// The entry's material.
    pub material: Material,
    /// What draws it ([`Scene::hair_technique`]): strands, volume, hybrid or auto under the
    /// strand renderer; patches or SATF draw the whole scene.
    pub technique: TechniqueKind,
}

/// A scene resolved into renderer inputs (CPU side; upload with the renderer).
#[derive(Clone, Debug)]
pub struct PreparedScene {
    /// The `[[hair]]` entries, in order (empty when the scene has no hair).
    pub objects: Vec<PreparedHair>,
    /// The head mesh, if the scene has one: the OBJ, or every generated head
    /// ([`Scene::generated_heads`], one per generated character) in one mesh.
    pub head: Option<TriMesh>,
    /// Directional lights, in the renderer's convention (direction of travel).
    pub lights: Vec<DirectionalLight>,
    /// Hair material of the first hair entry (defaults without hair); the head's colour.
    pub material: Material,
    /// Background (clear) color, linear RGB.
    pub background: Vec3,
    /// Constant ambient light (linear, per channel).
    pub ambient: f32,
    /// Strand technique settings from `[strands]`.
    pub strands: StrandSettings,
    /// Volume technique settings from `[volume]`.
    pub volume: VolumeSettings,
    /// Level-of-detail settings from `[hybrid]`.
    pub hybrid: HybridSettings,
}

impl PreparedScene {
    /// Load the scene's hair and head and convert its settings. Errors name the file or key.
    pub fn load(scene: &Scene) -> Result<PreparedScene, RenderError> {
        let settings = Self::load_settings(scene)?;
        let (assets, hair_mesh) = scene.load_hair_and_meshes()?;
        let objects = assets
            .into_iter()
            .zip(&scene.hair)
            .enumerate()
            .map(|(i, (asset, spec))| {
                Ok(PreparedHair {
                    asset,
                    material: hair_material(&spec.material)?,
                    technique: scene
                        .hair_technique(i)
                        .map_err(|e| RenderError::Invalid(format!("hair.{i}.technique: {e}")))?,
                })
            })
            .collect::<Result<Vec<_>, RenderError>>()?;
        let head = match scene.head_source() {
            // USD grooms often carry the head they were groomed on.
            HeadSource::None => hair_mesh,
            HeadSource::Obj(path) => Some(read_obj_mesh(&path)?),
            HeadSource::Generated(_) => {
                let meshes: Vec<TriMesh> =
                    scene.generated_heads().iter().map(|g| g.mesh(64)).collect();
                TriMesh::merge(&meshes)
            }
        };
        Ok(PreparedScene {
            objects,
            head,
            ..settings
        })
    }

    /// Every hair entry merged into one asset, in order (`None` without hair): what patches,
    /// SATF and the reference tracer draw. One entry is borrowed, several are merged (a copy).
    pub fn hair(&self) -> Option<Cow<'_, HairAsset>> {
        match self.objects.as_slice() {
            [] => None,
            [one] => Some(Cow::Borrowed(&one.asset)),
            many => {
                let assets: Vec<HairAsset> = many.iter().map(|o| o.asset.clone()).collect();
                // Merging valid assets cannot fail (there is at least one).
                HairAsset::merge_owned(assets).ok().map(Cow::Owned)
            }
        }
    }

    /// The first character's material (`None` without hair): what patches and SATF, which draw
    /// the characters merged, shade every strand with.
    pub fn first_hair(&self) -> Option<&Material> {
        self.objects.first().map(|o| &o.material)
    }

    /// The box around every hair entry (`None` without hair).
    pub fn hair_bounds(&self) -> Option<Aabb> {
        self.objects
            .iter()
            .map(|o| o.asset.bounds())
            .reduce(|a, b| a.union(&b))
    }

    /// Strands and segments of every hair entry together.
    pub fn hair_counts(&self) -> (usize, usize) {
        self.objects.iter().fold((0, 0), |(s, g), o| {
            (s + o.asset.strand_count(), g + o.asset.segment_count())
        })
    }

    /// What a frame clears its color target to: the scene's background, opaque.
    pub fn clear_color(&self) -> Option<wgpu::Color> {
        let bg = self.background;
        Some(wgpu::Color {
            r: bg.x.into(),
            g: bg.y.into(),
            b: bg.z.into(),
            a: 1.0,
        })
    }

    /// These hair and head with the settings of `scene` (after [`frame_bounds`] changed them).
    pub fn reload_settings(self, scene: &Scene) -> Result<PreparedScene, RenderError> {
        Ok(PreparedScene {
            objects: self.objects,
            head: self.head,
            ..Self::load_settings(scene)?
        })
    }

    /// The scene's lights, material, background and technique settings, without loading hair
    /// or head (no `objects`, `head` is `None`). Errors name the key.
    pub fn load_settings(scene: &Scene) -> Result<PreparedScene, RenderError> {
        let lights = scene
            .lights
            .iter()
            .map(|l| DirectionalLight {
                direction: -l.to_light(),
                color: l.color,
                intensity: l.intensity,
            })
            .collect();
        let material = scene
            .hair
            .first()
            .map(|h| hair_material(&h.material))
            .transpose()?
            .unwrap_or_default();
        let strands = strand_settings(scene)?;
        let volume = volume_settings(scene)?;
        let hybrid = hybrid_settings(scene)?;
        Ok(PreparedScene {
            objects: Vec::new(),
            head: None,
            lights,
            material,
            background: scene.background,
            ambient: scene.ambient,
            strands,
            volume,
            hybrid,
        })
    }

    /// The scene camera for a target of `size` pixels.
    pub fn camera(scene: &Scene, size: [u32; 2]) -> Camera {
        let c = &scene.camera;
        Camera::look_at(
            c.eye,
            c.target,
            c.up,
            c.fov_y_deg.to_radians(),
            c.near,
            c.far,
            size,
        )
    }
}

/// The renderer's material of a `[hair.material]` table (its fibre checked).
pub fn hair_material(m: &tress_scene::Material) -> Result<Material, RenderError> {
    Ok(Material {
        base_color: m.base_color,
        primary_color: m.primary_color,
        primary_exponent: m.primary_exponent,
        primary_shift: m.primary_shift,
        secondary_color: m.secondary_color,
        secondary_exponent: m.secondary_exponent,
        secondary_shift: m.secondary_shift,
        fiber: m.fiber()?,
        ..Material::default()
    })
}

/// The `[strands]` table: every key optional, unknown keys are errors naming key and line.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
struct StrandTable {
    width_px: Option<f32>,
    alpha: Option<f32>,
    shading: Option<String>,
    multiple_scattering: Option<bool>,
    coverage: Option<bool>,
    thickness_fade: Option<String>,
    oit: Option<String>,
    k: Option<u32>,
    ppll_nodes_per_pixel: Option<f32>,
    ppll_max_mib: Option<f64>,
    shortcut_k: Option<u32>,
    shadows: Option<bool>,
    shadow_map_size: Option<u32>,
    shadow_r: Option<f32>,
    shadow_alpha: Option<f32>,
    pcf_radius: Option<u32>,
    shadow_bias: Option<f32>,
    shadow_width_px: Option<f32>,
    shadow_mode: Option<String>,
    ao: Option<bool>,
}

/// Strand settings from the scene's `[strands]` table over [`StrandSettings::default`].
pub fn strand_settings(scene: &Scene) -> Result<StrandSettings, RenderError> {
    let t: StrandTable = scene.technique_settings("strands")?;
    let mut s = StrandSettings::default();
    macro_rules! set {
        ($($f:ident),*) => { $( if let Some(v) = t.$f { s.$f = v; } )* };
    }
    set!(
        width_px,
        alpha,
        multiple_scattering,
        coverage,
        k,
        ppll_nodes_per_pixel,
        shortcut_k,
        shadows,
        shadow_map_size,
        shadow_r,
        shadow_alpha,
        pcf_radius,
        shadow_bias,
        shadow_width_px,
        ao
    );
    if let Some(name) = &t.shadow_mode {
        s.shadow_mode = name.parse::<ShadowMode>()?;
    }
    if let Some(name) = &t.thickness_fade {
        s.thickness_fade = name.parse::<ThicknessFade>()?;
    }
    if let Some(name) = &t.shading {
        s.shading = name.parse::<Shading>()?;
    }
    if let Some(name) = &t.oit {
        s.oit = name.parse::<crate::strands::Oit>()?;
    }
    if let Some(mib) = t.ppll_max_mib {
        if !(mib.is_finite() && mib > 0.0) {
            return Err(RenderError::Invalid(
                "strands.ppll_max_mib must be positive".into(),
            ));
        }
        s.ppll_max_bytes = (mib * (1u64 << 20) as f64) as u64;
    }
    s.validate()?;
    Ok(s)
}

pub use crate::patches::scene::{
    PatchScene, PatchSource, load_patches, patch_settings, patch_source,
};

pub use crate::satf::scene::{ClusterSource, SatfScene, load_clusters, satf_settings};

/// The `[volume]` table: every key optional, unknown keys are errors naming key and line.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
struct VolumeTable {
    resolution: Option<u32>,
    screen_resolution: Option<bool>,
    min_resolution: Option<u32>,
    voxels_per_px: Option<f32>,
    voxelize: Option<String>,
    reconstruction_radius: Option<u32>,
    max_strands_per_voxel: Option<u32>,
    steps: Option<u32>,
    opacity: Option<String>,
    iso: Option<f32>,
    shade_samples: Option<u32>,
    highlights: Option<String>,
    skip_empty: Option<bool>,
    shadows: Option<bool>,
    occlusion: Option<String>,
    shadow_alpha: Option<f32>,
    shadow_step: Option<f32>,
    shadow_offset: Option<f32>,
    strand_width: Option<f32>,
    ao: Option<bool>,
    ao_radius: Option<f32>,
    ao_samples: Option<u32>,
    ao_intensity: Option<f32>,
    ao_texel: Option<u32>,
    budget_mib: Option<u32>,
}

/// Volume settings from the scene's `[volume]` table over [`VolumeSettings::default`].
pub fn volume_settings(scene: &Scene) -> Result<VolumeSettings, RenderError> {
    let t: VolumeTable = scene.technique_settings("volume")?;
    let mut s = VolumeSettings::default();
    macro_rules! set {
        ($($f:ident),*) => { $( if let Some(v) = t.$f { s.$f = v; } )* };
    }
    set!(
        resolution,
        screen_resolution,
        min_resolution,
        voxels_per_px,
        reconstruction_radius,
        max_strands_per_voxel,
        steps,
        iso,
        shade_samples,
        skip_empty,
        shadows,
        shadow_alpha,
        shadow_step,
        shadow_offset,
        strand_width,
        ao,
        ao_radius,
        ao_samples,
        ao_intensity,
        ao_texel,
        budget_mib
    );
    if let Some(name) = &t.voxelize {
        s.voxelize = crate::volume::parse_voxelize_mode(name)?;
    }
    if let Some(name) = &t.occlusion {
        s.occlusion = name.parse()?;
    }
    if let Some(name) = &t.opacity {
        s.opacity = name.parse()?;
    }
    if let Some(name) = &t.highlights {
        s.highlights = name.parse()?;
    }
    s.validate()?;
    Ok(s)
}

/// The `[hybrid]` table.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
struct HybridTable {
    lod: Option<f32>,
    near: Option<f32>,
    far: Option<f32>,
    transition: Option<String>,
    auto_near_px: Option<f32>,
    auto_far_px: Option<f32>,
    budget_ms: Option<f32>,
}

/// Level-of-detail settings from the scene's `[hybrid]` table over [`HybridSettings::default`]
/// (`lod` absent: the factor comes from the camera distance).
pub fn hybrid_settings(scene: &Scene) -> Result<HybridSettings, RenderError> {
    let t: HybridTable = scene.technique_settings("hybrid")?;
    let mut s = HybridSettings {
        lod: t.lod,
        budget_ms: t.budget_ms,
        ..HybridSettings::default()
    };
    if let Some(v) = t.near {
        s.near = v;
    }
    if let Some(v) = t.far {
        s.far = v;
    }
    if let Some(name) = &t.transition {
        s.transition = name.parse::<Transition>()?;
    }
    if let Some(v) = t.auto_near_px {
        s.auto_near_px = v;
    }
    if let Some(v) = t.auto_far_px {
        s.auto_far_px = v;
    }
    s.validate()?;
    Ok(s)
}

/// Read a head mesh from an OBJ, glTF (`.gltf`, `.glb`) or USD file
/// ([`tress_hair::formats::read_mesh`]: faces triangulated, normals from the file or the faces,
/// hostile indices rejected). Errors name the file.
pub fn read_obj_mesh(path: &Path) -> Result<TriMesh, RenderError> {
    let mesh = tress_hair::formats::read_mesh(path)?;
    crate::head::validate(&mesh)
        .map_err(|e| RenderError::setting(path.display().to_string(), e))?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    #[test]
    fn strand_table_overrides_defaults_and_rejects_unknown_keys() {
        let mut scene =
            Scene::from_str("[strands]\nk = 8\nshading = \"scheuermann\"\n", ".").unwrap();
        let s = strand_settings(&scene).unwrap();
        assert_eq!(s.k, 8);
        assert_eq!(s.shading, Shading::Scheuermann);
        assert_eq!(s.width_px, StrandSettings::default().width_px);
        scene.apply_override("strands.ppll_max_mib=1").unwrap();
        assert_eq!(strand_settings(&scene).unwrap().ppll_max_bytes, 1 << 20);

        let bad = Scene::from_str("\n[strands]\nkk = 8\n", ".").unwrap();
        let err = strand_settings(&bad).unwrap_err().to_string();
        assert!(err.contains("kk") && err.contains("line 3"), "{err}");
        let bad = Scene::from_str("[strands]\nk = 0\n", ".").unwrap();
        assert!(
            strand_settings(&bad)
                .unwrap_err()
                .to_string()
                .contains("strands.k")
        );
    }

    #[test]
    fn volume_and_hybrid_tables_override_defaults_and_name_bad_keys() {
        let mut scene = Scene::from_str(
            "[volume]\nresolution = 64\nvoxelize = \"vertices\"\n[hybrid]\nlod = 0.25\n\
             transition = \"dither\"\n[strands]\nshadow_mode = \"volume\"\nao = true\n",
            ".",
        )
        .unwrap();
        let v = volume_settings(&scene).unwrap();
        assert_eq!(
            (v.resolution, v.voxelize),
            (64, crate::VoxelizeMode::Vertices)
        );
        assert_eq!(v.steps, VolumeSettings::default().steps);
        let h = hybrid_settings(&scene).unwrap();
        assert_eq!((h.lod, h.transition), (Some(0.25), Transition::Dither));
        let st = strand_settings(&scene).unwrap();
        assert_eq!((st.shadow_mode, st.ao), (ShadowMode::Volume, true));
        scene.apply_override("volume.steps=64").unwrap();
        assert_eq!(volume_settings(&scene).unwrap().steps, 64);
        for (text, needle) in [
            ("[volume]\nsteps = 0\n", "volume.steps"),
            ("[volume]\nstep = 4\n", "step"),
            ("[volume]\nvoxelize = \"voxels\"\n", "voxels"),
            ("[hybrid]\nlod = 2.0\n", "hybrid.lod"),
            ("[hybrid]\ntransition = \"fade\"\n", "fade"),
            ("[strands]\nshadow_mode = \"dsm\"\n", "dsm"),
        ] {
            let scene = Scene::from_str(text, ".").unwrap();
            let err = volume_settings(&scene)
                .and(hybrid_settings(&scene).map(|_| VolumeSettings::default()))
                .and(strand_settings(&scene).map(|_| VolumeSettings::default()))
                .unwrap_err()
                .to_string();
            assert!(err.contains(needle), "{err} should name {needle}");
        }
    }

    #[test]
    fn lights_flip_to_the_renderer_convention() {
        let scene = Scene::from_str("[[light]]\ndirection = [0.0, 2.0, 0.0]\n", ".").unwrap();
        let p = PreparedScene::load(&scene).unwrap();
        assert_eq!(p.lights.len(), 1);
        // The scene points towards the light; the renderer stores the direction of travel.
        assert!((p.lights[0].direction - Vec3::NEG_Y).length() < 1e-6);
        assert!((p.lights[0].to_light().unwrap() - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn world_unit_defaults_follow_the_assets_unit() {
        let head = (Vec3::new(-12.0, -30.0, -12.0), Vec3::new(12.0, 12.0, 12.0));
        assert_eq!(unit_scale(head.0, head.1), 1.0);
        assert_eq!(unit_scale(head.0 * 0.01, head.1 * 0.01), 0.01);
        assert_eq!(unit_scale(head.0 * 10.0, head.1 * 10.0), 10.0);
        assert_eq!(unit_scale(Vec3::ZERO, Vec3::ZERO), 1.0);
        // The TressFX 4 mohawk, in metres.
        let mohawk = (Vec3::new(-0.105, 0.8, -0.45), Vec3::new(0.105, 1.41, 0.45));
        assert_eq!(unit_scale(mohawk.0, mohawk.1), 0.01);
        // A key the scene gives keeps its value; the others scale with their unit's power.
        let mut scene = Scene::from_str("[strands]\nshadow_bias = 0.2\n", ".").unwrap();
        frame_bounds(&mut scene, mohawk.0, mohawk.1);
        let p = PreparedScene::load_settings(&scene).unwrap();
        let d = (
            StrandSettings::default(),
            VolumeSettings::default(),
            HybridSettings::default(),
        );
        assert_eq!(p.strands.shadow_bias, 0.2);
        assert!((p.strands.shadow_r - d.0.shadow_r * 100.0).abs() < 1e-3);
        assert!((p.volume.ao_radius - d.1.ao_radius * 0.01).abs() < 1e-7);
        assert!((p.volume.strand_width - d.1.strand_width * 0.01).abs() < 1e-9);
        assert!((p.hybrid.near - d.2.near * 0.01).abs() < 1e-5);
        assert!((p.hybrid.far - d.2.far * 0.01).abs() < 1e-5);
        // Centimetres change nothing.
        let mut cm = Scene::from_str("", ".").unwrap();
        frame_bounds(&mut cm, head.0, head.1);
        assert!(cm.technique_table("strands").is_none_or(|t| t.is_empty()));
    }

    #[test]
    fn framing_puts_the_bounds_inside_the_view() {
        let mut scene = Scene::from_str("", ".").unwrap();
        let (min, max) = (Vec3::new(-3.0, -10.0, -2.0), Vec3::new(5.0, 4.0, 6.0));
        frame_bounds(&mut scene, min, max);
        let cam = PreparedScene::camera(&scene, [640, 360]);
        for i in 0..8 {
            let corner = Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            );
            let clip = cam.clip_from_world() * corner.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            assert!(
                ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0,
                "corner {corner} at {ndc}"
            );
            assert!(
                (0.0..=1.0).contains(&ndc.z),
                "corner {corner} depth {}",
                ndc.z
            );
        }
    }

    /// The area of the screen rectangle around the projected corners of (min, max).
    fn screen_rect_area(scene: &Scene, min: Vec3, max: Vec3) -> f32 {
        let cam = PreparedScene::camera(scene, [640, 360]);
        let (mut lo, mut hi) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
        for i in 0..8 {
            let corner = Vec3::select(
                glam::BVec3::new(i & 1 == 0, i & 2 == 0, i & 4 == 0),
                min,
                max,
            );
            let clip = cam.clip_from_world() * corner.extend(1.0);
            let ndc = clip.truncate().truncate() / clip.w;
            lo = lo.min(ndc);
            hi = hi.max(ndc);
        }
        (hi - lo).x * (hi - lo).y
    }

    #[test]
    fn a_mohawk_is_framed_across_its_largest_extents() {
        // The TressFX 4 mohawk's bounds (metres): thin across x, long along z.
        let (min, max) = (Vec3::new(-0.105, 0.8, -0.45), Vec3::new(0.105, 1.41, 0.45));
        let mut scene = Scene::from_str("", ".").unwrap();
        frame_bounds(&mut scene, min, max);
        let framed = screen_rect_area(&scene, min, max);
        // The same distance and target from the front three-quarter view.
        let mut front = scene.clone();
        let distance = (scene.camera.eye - scene.camera.target).length();
        front.camera.eye = scene.camera.target + FRONT_VIEW.normalize() * distance;
        let from_front = screen_rect_area(&front, min, max);
        // 1.28x at the distance that fits the box's corners (1.3x and more from the farther
        // distance a bounding sphere gave).
        assert!(
            framed > 1.2 * from_front,
            "framed {framed} vs front {from_front}"
        );
        // A head of hair about as wide as deep keeps the front view.
        let head = Vec3::new(22.0, 30.0, 24.0);
        assert_eq!(framing_direction(head), FRONT_VIEW.normalize());
        // The projected area is that of the box's faces: a unit cube along an axis shows one face.
        assert!((projected_area(Vec3::ONE, Vec3::Z) - 1.0).abs() < 1e-6);
        assert!((projected_area(Vec3::new(2.0, 3.0, 4.0), Vec3::X) - 12.0).abs() < 1e-6);
    }

    #[test]
    fn obj_meshes_load_with_normals_and_reject_garbage() {
        let dir = std::env::temp_dir().join(format!("tress-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("tri.obj");
        std::fs::write(&good, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let m = read_obj_mesh(&good).unwrap();
        assert_eq!(m.indices, vec![0, 1, 2]);
        assert!(m.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
        let bad = dir.join("bad.obj");
        std::fs::write(&bad, "v 0 0 0\nf 1 -2 3\n").unwrap();
        let err = read_obj_mesh(&bad).unwrap_err().to_string();
        assert!(err.contains("bad.obj"), "{err}");
        assert!(read_obj_mesh(&dir.join("missing.obj")).is_err());
    }
}
