//! The [`Scene`]: parsing, validation, overrides, writing, and loading its hair.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Affine3A, Vec3};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use toml::de::{DeTable, ValueDeserializer};
use tress_hair::generate::{self, Head, HeadShape, Style, TriMesh};
use tress_hair::{HairAsset, HairError, formats};

use crate::SceneError;
use crate::error::one_line;
use crate::overrides;
use crate::parts::{Camera, HairSpec, HeadSpec, Light, Output, color, validate_lights};

use crate::technique::TechniqueKind;

/// The ambient light of a scene that does not set `ambient` (linear, per channel).
pub const DEFAULT_AMBIENT: f32 = 0.08;

/// A scene: camera, lights, hair assets, head, output image and technique settings.
///
/// Built from TOML with [`Scene::from_path`] or [`Scene::from_str`]; every key has a default
/// (see the crate docs), so an empty file is a valid scene. Unknown keys are errors naming the
/// key and its line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Scene {
    /// The technique to render with: one of [`crate::TECHNIQUES`].
    pub technique: String,
    /// Background color (linear RGB).
    pub background: Vec3,
    /// Constant ambient light of every technique's shading and the reference tracer's sky
    /// (linear, per channel; default [`DEFAULT_AMBIENT`]).
    pub ambient: f32,
    /// `[camera]`.
    pub camera: Camera,
    /// `[[light]]`: directional lights.
    #[serde(rename = "light")]
    pub lights: Vec<Light>,
    /// `[[hair]]`: the hair assets, in order.
    pub hair: Vec<HairSpec>,
    /// `[head]`: the head mesh.
    pub head: HeadSpec,
    /// `[output]`: the image size.
    pub output: Output,
    /// `[strands]`: settings of the strand rasterizer, read with [`Scene::technique_settings`].
    #[serde(skip_serializing_if = "toml::Table::is_empty")]
    pub strands: toml::Table,
    /// `[volume]`: settings of the volume raymarcher.
    #[serde(skip_serializing_if = "toml::Table::is_empty")]
    pub volume: toml::Table,
    /// `[hybrid]`: settings of the level-of-detail blend.
    #[serde(skip_serializing_if = "toml::Table::is_empty")]
    pub hybrid: toml::Table,
    /// `[patches]`: settings of the polygon-patch technique.
    #[serde(skip_serializing_if = "toml::Table::is_empty")]
    pub patches: toml::Table,
    /// `[satf]`: settings of the SATF technique.
    #[serde(skip_serializing_if = "toml::Table::is_empty")]
    pub satf: toml::Table,
    /// `[simulation]`: settings of the strand simulation, read with
    /// [`Scene::simulation_settings`].
    #[serde(skip_serializing_if = "toml::Table::is_empty")]
    pub simulation: toml::Table,
    /// Folder that relative paths (hair files, head OBJ) are resolved against: the scene file's
    /// folder. Not part of the file.
    #[serde(skip)]
    pub base_dir: PathBuf,
    /// Where the scene was read from, to position errors in technique tables.
    #[serde(skip)]
    origin: Origin,
}

impl Default for Scene {
    /// Strands technique, grey background `[0.2, 0.2, 0.2]`, the default camera, the two default
    /// lights ([`Light::default_rig`]), no hair, the generated head, 1280 × 720.
    fn default() -> Self {
        Scene {
            technique: "strands".into(),
            background: Vec3::splat(0.2),
            ambient: DEFAULT_AMBIENT,
            camera: Camera::default(),
            lights: Light::default_rig(),
            hair: Vec::new(),
            head: HeadSpec::default(),
            output: Output::default(),
            strands: toml::Table::new(),
            volume: toml::Table::new(),
            hybrid: toml::Table::new(),
            patches: toml::Table::new(),
            satf: toml::Table::new(),
            simulation: toml::Table::new(),
            base_dir: PathBuf::new(),
            origin: Origin::default(),
        }
    }
}

/// The source text of a scene (and its file), kept to give line numbers for errors found later in
/// technique tables. It takes no part in comparisons: scenes with equal contents are equal.
#[derive(Clone, Default)]
struct Origin {
    path: Option<PathBuf>,
    text: Option<Arc<str>>,
}

impl PartialEq for Origin {
    fn eq(&self, _: &Origin) -> bool {
        true
    }
}

impl fmt::Debug for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Origin")
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

/// What to draw as the head (see [`HeadSpec`]).
#[derive(Clone, Debug, PartialEq)]
pub enum HeadSource {
    /// No head.
    None,
    /// A mesh file at this path (resolved against the scene's folder): OBJ, glTF or USD, read
    /// with [`tress_hair::formats::read_mesh`].
    Obj(PathBuf),
    /// The generated head (see [`GeneratedHead`]).
    Generated(GeneratedHead),
}

/// The generated head: an ellipsoid, what it is drawn as, and where it is placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeneratedHead {
    /// The ellipsoid, in the space the hair generator grows strands from.
    pub head: Head,
    /// What it is drawn as.
    pub shape: HeadShape,
    /// The transform of the `[[hair]]` entry whose generator the head was made for (the first
    /// one with a generator; the identity without one), so the head moves with its hair.
    pub placement: Affine3A,
}

impl GeneratedHead {
    /// The placed head's triangle mesh ([`HeadShape::mesh`] with `subdivisions`, then moved by
    /// the placement).
    pub fn mesh(&self, subdivisions: u32) -> TriMesh {
        let mut mesh = self.shape.mesh(&self.head, subdivisions);
        mesh.transform(self.placement);
        mesh
    }

    /// The placed head's centre.
    pub fn center(&self) -> Vec3 {
        self.placement.transform_point3(self.head.center)
    }
}

impl Scene {
    /// Read and validate a scene file. Relative paths in it are relative to its folder. Errors
    /// name the file.
    pub fn from_path(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError::from(e).in_file(path))?;
        let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut scene = Scene::from_str(&text, base_dir).map_err(|e| e.in_file(path))?;
        scene.origin.path = Some(path.to_path_buf());
        Ok(scene)
    }

    /// Parse and validate scene text; relative paths resolve against `base_dir`.
    pub fn from_str(text: &str, base_dir: impl Into<PathBuf>) -> Result<Scene, SceneError> {
        let mut scene: Scene = toml::from_str(text).map_err(|e| SceneError::from_toml(&e, text))?;
        scene.base_dir = base_dir.into();
        scene.origin = Origin {
            path: None,
            text: Some(text.into()),
        };
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as TOML text that [`Scene::from_str`] reads back to an equal scene.
    pub fn to_toml_string(&self) -> Result<String, SceneError> {
        toml::to_string(self).map_err(|e| SceneError::Serialize(one_line(&e.to_string())))
    }

    /// Apply one `--set key=value` override (see the crate docs for the syntax), then validate.
    /// On error the scene is unchanged and the error names the override.
    pub fn apply_override(&mut self, set: &str) -> Result<(), SceneError> {
        let fail = |reason: String| SceneError::Override {
            set: set.to_owned(),
            reason,
        };
        let (key, value) = overrides::split(set).map_err(fail)?;
        let mut table = match toml::Value::try_from(&*self) {
            Ok(toml::Value::Table(t)) => t,
            Ok(_) => return Err(fail("the scene is not a table".into())),
            Err(e) => return Err(fail(one_line(&e.to_string()))),
        };
        overrides::set(&mut table, key, overrides::parse_value(value)).map_err(fail)?;
        let mut scene: Scene = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| fail(one_line(&e.to_string())))?;
        scene.base_dir = self.base_dir.clone();
        scene.origin = self.origin.clone();
        scene.validate().map_err(|e| fail(e.to_string()))?;
        *self = scene;
        Ok(())
    }

    /// Apply several overrides in order (see [`Scene::apply_override`]).
    pub fn apply_overrides<S: AsRef<str>>(
        &mut self,
        sets: impl IntoIterator<Item = S>,
    ) -> Result<(), SceneError> {
        sets.into_iter()
            .try_for_each(|s| self.apply_override(s.as_ref()))
    }

    /// Check every value's range and the consistency between values. [`Scene::from_str`],
    /// [`Scene::from_path`] and [`Scene::apply_override`] call it; call it after changing a scene
    /// in code.
    pub fn validate(&self) -> Result<(), SceneError> {
        if let Err(e) = self.technique.parse::<TechniqueKind>() {
            return Err(SceneError::invalid("technique", e.to_string()));
        }
        color("background", self.background)?;
        if !(self.ambient >= 0.0 && self.ambient.is_finite()) {
            return Err(SceneError::invalid(
                "ambient",
                format!("must be finite and non-negative, got {}", self.ambient),
            ));
        }
        self.camera.validate()?;
        validate_lights(&self.lights)?;
        for (i, h) in self.hair.iter().enumerate() {
            h.validate(&format!("hair.{i}"))?;
        }
        self.head.validate()?;
        if !self.simulation.is_empty() {
            self.simulation_settings()?;
        }
        self.output.validate()
    }

    /// `[simulation]` with every absent key at its default, checked: a misspelt key is an error
    /// naming it (and its line, when it came from the scene file), a value out of range an
    /// error naming its dotted key.
    pub fn simulation_settings(&self) -> Result<tress_sim::SimSettings, SceneError> {
        let settings: tress_sim::SimSettings =
            match toml::Value::Table(self.simulation.clone()).try_into() {
                Ok(s) => s,
                Err(plain) => {
                    return Err(self
                        .locate_table_error::<tress_sim::SimSettings>("simulation")
                        .unwrap_or_else(|| {
                            SceneError::invalid("simulation", one_line(&plain.to_string()))
                        }));
                }
            };
        settings.validate().map_err(sim_error)?;
        Ok(settings)
    }

    /// The settings table of a technique (one of [`crate::TECHNIQUES`]), `None` for an unknown name.
    pub fn technique_table(&self, name: &str) -> Option<&toml::Table> {
        Some(match name.parse::<TechniqueKind>().ok()? {
            TechniqueKind::Strands => &self.strands,
            TechniqueKind::Volume => &self.volume,
            // `auto` chooses among strands, volume and hybrid with `[hybrid]`'s thresholds.
            TechniqueKind::Hybrid | TechniqueKind::Auto => &self.hybrid,
            TechniqueKind::Patches => &self.patches,
            TechniqueKind::Satf => &self.satf,
        })
    }

    /// The scene's technique ([`Scene::validate`] checks that `technique` names one).
    pub fn technique_kind(&self) -> Result<TechniqueKind, crate::UnknownTechnique> {
        self.technique.parse()
    }

    /// The technique that draws `[[hair]]` entry `index`: its own `technique` when the scene's
    /// is one of the strand renderer's, else the scene's (patches and SATF draw every entry).
    pub fn hair_technique(&self, index: usize) -> Result<TechniqueKind, crate::UnknownTechnique> {
        let scene = self.technique_kind()?;
        match self.hair.get(index).and_then(|h| h.technique.as_deref()) {
            Some(own) if scene.per_object() => own.parse(),
            _ => Ok(scene),
        }
    }

    /// Draw everything with `technique`: the scene's `technique`, and no `[[hair]]` entry keeps
    /// a technique of its own (what `tress render --technique` and the viewer's switch mean).
    /// Errors, and leaves the scene unchanged, for an unknown name.
    pub fn force_technique(&mut self, technique: &str) -> Result<(), SceneError> {
        if let Err(e) = technique.parse::<TechniqueKind>() {
            return Err(SceneError::invalid("technique", e.to_string()));
        }
        self.technique = technique.to_owned();
        for h in &mut self.hair {
            h.technique = None;
        }
        Ok(())
    }

    /// Deserialize a technique's table into the technique's settings struct.
    ///
    /// Give `T` `#[serde(deny_unknown_fields, default)]`: then a misspelt key is an error naming
    /// the key and, when the key came from the scene file, its line (and the file), exactly like
    /// errors in the rest of the scene. Keys set by overrides are named without a line.
    pub fn technique_settings<T: DeserializeOwned>(&self, name: &str) -> Result<T, SceneError> {
        let table = match name.parse::<TechniqueKind>() {
            Ok(_) => self.technique_table(name).expect("a technique's table"),
            Err(e) => return Err(SceneError::invalid("technique", e.to_string())),
        };
        match toml::Value::Table(table.clone()).try_into::<T>() {
            Ok(settings) => Ok(settings),
            Err(plain) => Err(self
                .locate_technique_error::<T>(name)
                .unwrap_or_else(|| SceneError::invalid(name, one_line(&plain.to_string())))),
        }
    }

    fn locate_technique_error<T: DeserializeOwned>(&self, name: &str) -> Option<SceneError> {
        self.locate_table_error::<T>(name)
    }

    /// Deserialize the top-level table `name` as written in the source text, to find the line of
    /// an error. `None` when there is no text, no such table in it, or no error in it (the error
    /// came from an override or a change in code).
    fn locate_table_error<T: DeserializeOwned>(&self, name: &str) -> Option<SceneError> {
        let text = self.origin.text.as_deref()?;
        let root = DeTable::parse(text).ok()?;
        let (_, value) = root
            .get_ref()
            .iter()
            .find(|(k, _)| k.get_ref().as_ref() == name)?;
        let error = T::deserialize(ValueDeserializer::from(value.clone())).err()?;
        let error = SceneError::from_toml(&error, text);
        Some(match &self.origin.path {
            Some(path) => error.in_file(path),
            None => error,
        })
    }

    /// A path from the scene resolved against [`Scene::base_dir`] (absolute paths are kept).
    pub fn resolve(&self, path: &Path) -> PathBuf {
        self.base_dir.join(path)
    }

    /// What to draw as the head: the OBJ file, the generated head (with the centre, radii and
    /// shape of `[head]` or, absent, of the first generated hair entry's style), or nothing.
    pub fn head_source(&self) -> HeadSource {
        if let Some(obj) = &self.head.obj {
            return HeadSource::Obj(self.resolve(obj));
        }
        if self.head.generated == Some(false) {
            return HeadSource::None;
        }
        let generated = self.hair.iter().find_map(|h| {
            let style = h.generator.as_ref()?.style.parse::<Style>().ok()?;
            Some((style, h.transform.affine()))
        });
        let style = generated.map(|(s, _)| s);
        let base = style.map(generate::head_for).unwrap_or_default();
        let shape = self
            .head
            .shape
            .as_deref()
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| style.map(generate::shape_for).unwrap_or_default());
        HeadSource::Generated(GeneratedHead {
            head: Head {
                center: self.head.center.unwrap_or(base.center),
                radii: self.head.radii.unwrap_or(base.radii),
            },
            shape,
            placement: generated.map_or(Affine3A::IDENTITY, |(_, a)| a),
        })
    }

    /// Every generated head the scene draws: with a generated head ([`Scene::head_source`]),
    /// one for each `[[hair]]` entry with a generator, placed by its transform and shaped for
    /// its style (a crowd of generated characters has a head each), the same placed head once;
    /// the one of [`Scene::head_source`] when no entry has a generator; none with an OBJ head
    /// or `generated = false`. The first is [`Scene::head_source`]'s.
    pub fn generated_heads(&self) -> Vec<GeneratedHead> {
        let HeadSource::Generated(first) = self.head_source() else {
            return Vec::new();
        };
        let mut heads = vec![first];
        for h in &self.hair {
            let Some(style) = h
                .generator
                .as_ref()
                .and_then(|g| g.style.parse::<Style>().ok())
            else {
                continue;
            };
            let base = generate::head_for(style);
            let head = GeneratedHead {
                head: Head {
                    center: self.head.center.unwrap_or(base.center),
                    radii: self.head.radii.unwrap_or(base.radii),
                },
                shape: self
                    .head
                    .shape
                    .as_deref()
                    .and_then(|s| s.parse().ok())
                    .unwrap_or_else(|| generate::shape_for(style)),
                placement: h.transform.affine(),
            };
            if !heads.contains(&head) {
                heads.push(head);
            }
        }
        heads
    }

    /// Read or generate every `[[hair]]` entry, in order: the files (merged) or the generator,
    /// then follow hairs, then the `strand_ratio` subset (seed 0), then the transform (which also
    /// scales per-vertex thickness by `scale`). Errors name the entry.
    pub fn load_hair(&self) -> Result<Vec<HairAsset>, SceneError> {
        Ok(self.load_hair_and_meshes()?.0)
    }

    /// [`Scene::load_hair`], and the `Mesh` prims that came in USD hair files (merged, world
    /// space, before the entries' transforms; `None` when there were none).
    pub fn load_hair_and_meshes(&self) -> Result<(Vec<HairAsset>, Option<TriMesh>), SceneError> {
        let mut assets = Vec::with_capacity(self.hair.len());
        let mut mesh: Option<TriMesh> = None;
        for (index, spec) in self.hair.iter().enumerate() {
            let (asset, found) = self.load_one(spec).map_err(|e| e.at_hair(index))?;
            assets.push(asset);
            for m in found {
                match &mut mesh {
                    None => mesh = Some(m),
                    Some(all) => all.append(&m),
                }
            }
        }
        Ok((assets, mesh))
    }

    fn load_one(&self, spec: &HairSpec) -> Result<(HairAsset, Vec<TriMesh>), LoadError> {
        let mut meshes = Vec::new();
        let mut asset = match &spec.generator {
            Some(g) if spec.files.is_empty() => {
                let (style, params) = g.style_params().map_err(LoadError::Scene)?;
                generate::generate(style, &params)?
            }
            _ => {
                let paths: Vec<PathBuf> = spec.files.iter().map(|p| self.resolve(p)).collect();
                let defaults = formats::ReadOptions::default();
                let options = formats::ReadOptions {
                    cubic_segments: spec.cubic_segments.unwrap_or(defaults.cubic_segments),
                    frame: spec.frame.unwrap_or(defaults.frame),
                };
                let (asset, found) = formats::load_paths(&paths, &options)?;
                meshes.extend(found.into_iter().filter_map(|(_, d)| d.mesh));
                asset
            }
        };
        if let Some(follow) = &spec.follow {
            asset = asset.with_follow_hairs(&follow.into())?;
        }
        if spec.strand_ratio < 1.0 {
            asset = asset.subset(spec.strand_ratio, 0)?;
        }
        if !spec.transform.is_identity() {
            asset.transform(spec.transform.affine())?;
            let scale = spec.transform.scale;
            if let Some(t) = asset.thickness().filter(|_| scale != 1.0) {
                let scaled = t.iter().map(|x| x * scale).collect();
                asset = asset.with_thickness(scaled)?;
            }
            // A uniform scale and a rotation: normals turn with the rotation alone.
            for m in &mut meshes {
                m.transform(spec.transform.affine());
            }
        }
        Ok((asset, meshes))
    }
}

/// An error while loading one hair entry, before its index is attached.
enum LoadError {
    Hair(HairError),
    Scene(SceneError),
}

impl From<HairError> for LoadError {
    fn from(e: HairError) -> Self {
        LoadError::Hair(e)
    }
}

impl LoadError {
    fn at_hair(self, index: usize) -> SceneError {
        match self {
            LoadError::Hair(source) => SceneError::Hair { index, source },
            LoadError::Scene(SceneError::Invalid { key, reason }) => {
                SceneError::invalid(format!("hair.{index}.{key}"), reason)
            }
            LoadError::Scene(e) => e,
        }
    }
}

/// A simulation setting's error as a scene error naming its key.
pub(crate) fn sim_error(e: tress_sim::SimError) -> SceneError {
    match e {
        tress_sim::SimError::Setting { key, reason } => SceneError::invalid(key, reason),
        other => SceneError::invalid("simulation", other.to_string()),
    }
}
