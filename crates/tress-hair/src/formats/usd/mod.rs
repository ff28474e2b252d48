//! USD (`.usda`, `.usdc`, `.usdz`) curves and meshes, read and written with the `openusd` crate.
//!
//! # Reading
//!
//! The stage is opened and composed (references, payloads, sublayers, variants) and every
//! active prim is visited. A `.usdc` file whose one layer has no composition arcs is read
//! without a stage, straight from the caller's bytes (`usd/layer.rs`: the same prims, values and
//! transforms, several times faster); anything that layer path does not model goes to the stage.
//! Either way the prims are read by `usd/schema.rs`:
//!
//! - `BasisCurves`: `curveVertexCounts`, `points`, `type` (`linear`, or `cubic` with `basis`
//!   `bezier`, `bspline` or `catmullRom` and `wrap` `nonperiodic`, `pinned` or `periodic`,
//!   tessellated by the [rule of `curves`](super::curves); USD's fallbacks `cubic`, `bezier`,
//!   `nonperiodic` apply when unauthored), `widths` (or `primvars:widths`) → thickness with its
//!   `interpolation` (`constant`, `uniform`, `varying`, `vertex`), `primvars:displayColor`
//!   (indexed or not) → color, `primvars:displayOpacity` → transparency (1 − opacity),
//!   `primvars:st` when `uniform` → strand UV.
//! - `NurbsCurves`: `order`, `knots`, `pointWeights`, the same primvars (tessellated per knot
//!   span; `ranges` are not applied).
//! - `Mesh`: `points`, `faceVertexCounts`, `faceVertexIndices` (fan-triangulated, `orientation`
//!   honoured) → the head/body mesh ([`read_usd_mesh`]).
//!
//! Each prim's world transform is its `xformOp`s composed up the hierarchy
//! (`!resetXformStack!` honoured), so several grooms in one stage merge as several files do.
//! Attributes with only time samples are read at the earliest one, except `points`, read at
//! its [`ReadOptions::frame`]-th time sample (an animated cache: [`UsdInfo::frames`] counts the
//! samples and [`UsdInfo::fps`] is their rate). Everything else (materials,
//! `HermiteCurves`, `normals`, other primvars) is ignored. A composition error (an arc cycle, a
//! missing layer) is an error naming it.
//!
//! # Validation
//!
//! openusd 0.6 trusts the counts in `.usdc` files; a `.usdc` file given to tress is first
//! checked by `usdc_check` (counts against the file's size, see there), and a panic inside
//! openusd becomes an error. Layers reached through references and the layer inside a `.usdz`
//! package are not pre-checked (see ARCHITECTURE.md).
//!
//! # Writing
//!
//! [`write_usd`] writes one linear `BasisCurves` prim `/Hair` with `widths` and
//! `primvars:displayColor` per vertex, `primvars:displayOpacity` when the asset has
//! transparency, and uniform `primvars:st` for strand UVs, as `.usda` text or `.usdc` binary.

mod layer;
mod memory;
mod schema;
mod usdc_check;
mod write;

use std::collections::HashMap;
use std::path::Path;

use glam::DMat4;
use openusd::schemas::geom::{Imageable, Xformable};
use openusd::sdf;
use openusd::usd::{Prim, PrimPredicate, SchemaBase, SchemaKind, Stage, TimeCode};

use memory::MemoryResolver;
use schema::Attrs;

use super::curves::ReadOptions;
use crate::generate::TriMesh;
use crate::{HairAsset, HairError};

pub use write::{UsdFlavor, write_usd, write_usd_animated};

const FORMAT: &str = "USD";

fn err(reason: impl std::fmt::Display) -> HairError {
    HairError::format(FORMAT, one_line(&reason.to_string()))
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// What a read found: the prims used and ignored.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UsdInfo {
    /// Curves prims read, by path.
    pub prims: Vec<String>,
    /// Mesh prims read, by path.
    pub meshes: Vec<String>,
    /// Frames of an animated cache: the most `points` time samples over the curves prims (1 for
    /// a still stage; 0 only in a default value, never from a read).
    pub frames: u32,
    /// Frames a second of an animated cache: the stage's `timeCodesPerSecond` over the mean
    /// spacing of the time samples of the prim with the most; `None` for a still stage.
    pub fps: Option<f64>,
}

/// A composed stage's curves and meshes.
#[derive(Clone, Debug)]
pub struct UsdContents {
    /// Every curves prim merged (`None`: the stage has no curves).
    pub hair: Option<HairAsset>,
    /// Every mesh prim merged (`None`: the stage has no meshes).
    pub mesh: Option<TriMesh>,
    /// What was read.
    pub info: UsdInfo,
}

/// Any prim viewed as `Xformable` (openusd's xformOp composition works on any prim).
struct AnyPrim(Prim);

impl SchemaBase for AnyPrim {
    const KIND: SchemaKind = SchemaKind::ConcreteTyped;
    fn prim(&self) -> &Prim {
        &self.0
    }
}
impl Imageable for AnyPrim {}
impl Xformable for AnyPrim {}

/// Read a USD file from disk (its extension picks the flavour; references resolve beside it).
pub fn read_usd(path: &Path, options: &ReadOptions) -> Result<UsdContents, HairError> {
    let name = path
        .to_str()
        .ok_or_else(|| err("the file name is not UTF-8"))?;
    // openusd reports a missing file as an unresolvable asset; say it plainly.
    let bytes = std::fs::read(path).map_err(HairError::from)?;
    check_crate(&bytes)?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if let Some(c) = direct(&bytes, ext, options) {
        return Ok(c);
    }
    guarded(|| {
        let stage = Stage::open(name).map_err(|e| err(format!("{e:#}")))?;
        contents(&stage, options)
    })
}

/// Run openusd, turning a panic inside it (its reader indexes tables with values from the file
/// and has `todo!()`s; `usdc_check` refuses what is known to reach them) into an error that
/// prints nothing else ([`crate::panic_guard`]).
fn guarded<T>(f: impl FnOnce() -> Result<T, HairError>) -> Result<T, HairError> {
    crate::panic_guard::quietly(f)
        .unwrap_or_else(|| Err(err("openusd could not read the file (it panicked)")))
}

/// [`usdc_check::check`] for binary files (text and packages pass through).
fn check_crate(bytes: &[u8]) -> Result<(), HairError> {
    if bytes.starts_with(b"PXR-USDC") {
        usdc_check::check(bytes).map_err(err)?;
    }
    Ok(())
}

/// Read a USD file from memory; `extension` (`usda`, `usdc` or `usdz`) says which flavour it is.
/// References to other files cannot resolve.
pub fn read_usd_bytes(
    bytes: &[u8],
    extension: &str,
    options: &ReadOptions,
) -> Result<UsdContents, HairError> {
    if extension == "usdc" {
        if !bytes.starts_with(b"PXR-USDC") {
            return Err(err(format!(
                "not a .usdc file: it starts with \"{}\" instead of \"PXR-USDC\"",
                bytes[..bytes.len().min(8)].escape_ascii()
            )));
        }
        usdc_check::check(bytes).map_err(err)?;
        if let Some(c) = direct(bytes, extension, options) {
            return Ok(c);
        }
    }
    read_through_stage(bytes, extension, options)
}

/// [`layer::read`] for a file that openusd reads as a crate file (`.usdc`, or `.usd` starting
/// with the crate magic); other files: `None`, the stage reads them.
fn direct(bytes: &[u8], extension: &str, options: &ReadOptions) -> Option<UsdContents> {
    let crate_ext = extension.eq_ignore_ascii_case("usdc") || extension.eq_ignore_ascii_case("usd");
    if crate_ext && bytes.starts_with(b"PXR-USDC") {
        layer::read(bytes, options)
    } else {
        None
    }
}

/// [`read_usd_bytes`] through a composed stage, whatever the file holds.
pub(super) fn read_through_stage(
    bytes: &[u8],
    extension: &str,
    options: &ReadOptions,
) -> Result<UsdContents, HairError> {
    let name = format!("memory.{extension}");
    let resolver = MemoryResolver::new(&name, bytes);
    guarded(|| {
        let stage = Stage::builder()
            .resolver(resolver)
            .open(&name)
            .map_err(|e| err(format!("{e:#}")))?;
        contents(&stage, options)
    })
}

/// The head/body mesh of a USD file: every `Mesh` prim merged, in world space.
pub fn read_usd_mesh(path: &Path) -> Result<TriMesh, HairError> {
    let c = read_usd(path, &ReadOptions::default()).map_err(|e| e.in_file(path))?;
    c.mesh
        .ok_or_else(|| err("the stage has no Mesh prims").in_file(path))
}

/// Most prims a stage may have (a bound for hostile files; a groom has a handful).
const MAX_PRIMS: usize = 1 << 20;

/// Walk the prim hierarchy before openusd traverses it, refusing child names that are not prim
/// names and stages beyond [`MAX_PRIMS`]: openusd appends a child name to its parent's path as
/// written, so a damaged file whose child list names `.` or `..` sends its traversal round a
/// cycle forever (one changed byte in a test file took it to 10 GB).
fn check_hierarchy(stage: &Stage) -> Result<(), HairError> {
    let mut stack = vec![sdf::Path::abs_root()];
    let mut prims = 0usize;
    while let Some(path) = stack.pop() {
        let names = stage
            .prim(path.clone())
            .child_names()
            .map_err(|e| err(format!("{e:#}")))?;
        for name in names {
            let name = name.as_str();
            if !is_identifier(name) {
                return Err(err(format!(
                    "prim {path} has a child named \"{}\", which is not a prim name",
                    name.escape_debug()
                )));
            }
            prims += 1;
            if prims > MAX_PRIMS {
                return Err(err(format!("the stage has more than {MAX_PRIMS} prims")));
            }
            let child = path.append_path(name).map_err(|e| err(format!("{e:#}")))?;
            stack.push(child);
        }
    }
    Ok(())
}

/// A USD identifier: letters, digits (not first) and `_`, or any non-ASCII character.
fn is_identifier(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with(|c: char| c.is_ascii_digit())
        && name
            .chars()
            .all(|c| c.is_alphanumeric() || c == '_' || !c.is_ascii())
}

/// Refuse an `xformOpOrder` entry that is not a property name (`a:b:c`, optionally after
/// `!invert!`) or `!resetXformStack!`: openusd builds a property path from each entry, and a
/// damaged name (`xformOp}rotateY`, one changed byte in a test file) sent its path parsing into
/// an endless loop.
fn check_op_order(prim: &AnyPrim, path: &sdf::Path) -> Result<(), HairError> {
    match prim
        .xform_op_order()
        .map_err(|e| err(format!("{path}: {e:#}")))?
    {
        Some(order) => check_op_names(&order, path),
        None => Ok(()),
    }
}

/// [`check_op_order`]'s test of each entry.
fn check_op_names(order: &[String], path: &sdf::Path) -> Result<(), HairError> {
    for op in order {
        let name = op.strip_prefix("!invert!").unwrap_or(op);
        if op != "!resetXformStack!" && !name.split(':').all(is_identifier) {
            return Err(err(format!(
                "{path}: xformOpOrder names \"{}\", which is not a property name",
                op.escape_debug()
            )));
        }
    }
    Ok(())
}

/// The curves and meshes found so far, merged by [`Found::finish`].
#[derive(Default)]
struct Found {
    assets: Vec<HairAsset>,
    meshes: Vec<TriMesh>,
    info: UsdInfo,
}

impl Found {
    /// Read the prim `prim` of schema `ty` (`BasisCurves`, `NurbsCurves` or `Mesh`).
    fn add(
        &mut self,
        prim: &impl Attrs,
        ty: &str,
        world: DMat4,
        options: &ReadOptions,
    ) -> Result<(), HairError> {
        let where_ = prim.prim_path().to_string();
        if ty == "Mesh" {
            self.meshes.push(schema::mesh(prim, &where_, world)?);
            self.info.meshes.push(where_);
            return Ok(());
        }
        let set = schema::curve_set(prim, ty, &where_, world)?;
        self.info.prims.push(where_);
        if let Some(a) = set.into_asset(options).map_err(in_format)? {
            self.assets.push(a);
        }
        Ok(())
    }

    fn finish(mut self) -> Result<UsdContents, HairError> {
        self.info.frames = self.info.frames.max(1);
        let hair = if self.assets.is_empty() {
            None
        } else {
            Some(HairAsset::merge_owned(self.assets).map_err(in_format)?)
        };
        let mesh = merge_meshes(self.meshes);
        Ok(UsdContents {
            hair,
            mesh,
            info: self.info,
        })
    }
}

fn contents(stage: &Stage, options: &ReadOptions) -> Result<UsdContents, HairError> {
    check_hierarchy(stage)?;
    let mut paths = Vec::new();
    stage
        .traverse(PrimPredicate::DEFAULT, |p| paths.push(p.clone()))
        .map_err(|e| err(format!("{e:#}")))?;
    let mut worlds: HashMap<String, DMat4> = HashMap::new();
    let mut found = Found::default();
    for path in &paths {
        let prim = stage.prim(path.clone());
        let ty = prim.type_name().map_err(|e| err(format!("{e:#}")))?;
        let ty = ty.as_ref().map(|t| t.as_str()).unwrap_or("");
        if !matches!(ty, "BasisCurves" | "NurbsCurves" | "Mesh") {
            continue;
        }
        let world = world_transform(stage, path, &mut worlds)?;
        let at = schema::AtFrame {
            prim: &prim,
            frame: options.frame,
        };
        found.add(&at, ty, world, options)?;
        if ty != "Mesh" {
            let times = schema::point_times(&prim)?;
            if times.len() > found.info.frames as usize {
                found.info.frames = u32::try_from(times.len()).unwrap_or(u32::MAX);
                found.info.fps = frames_per_second(&times, stage.time_codes_per_second());
            }
        }
    }
    if let Some(e) = stage.composition_errors().first() {
        return Err(err(format!("composition error: {e}")));
    }
    found.finish()
}

/// Frames a second of time samples at `times` (time codes, ascending), `codes_per_second` time
/// codes a second: one frame a mean spacing. `None` for fewer than two samples or a rate that
/// is not positive and finite.
fn frames_per_second(times: &[f64], codes_per_second: f64) -> Option<f64> {
    let (first, last) = (times.first()?, times.last()?);
    let spacing = (last - first) / (times.len() - 1) as f64;
    let fps = codes_per_second / spacing;
    (fps.is_finite() && fps > 0.0).then_some(fps)
}

fn in_format(e: HairError) -> HairError {
    match e {
        HairError::Invalid(reason) => HairError::format(FORMAT, reason),
        other => other,
    }
}

/// Local-to-world of the prim at `path`: its ancestors' xformOps composed (column vectors).
fn world_transform(
    stage: &Stage,
    path: &sdf::Path,
    cache: &mut HashMap<String, DMat4>,
) -> Result<DMat4, HairError> {
    if let Some(m) = cache.get(path.as_str()) {
        return Ok(*m);
    }
    let prim = AnyPrim(stage.prim(path.clone()));
    check_op_order(&prim, path)?;
    let local = prim
        .local_to_parent_transform(TimeCode::EARLIEST)
        .map_err(|e| err(format!("{}: {e:#}", path.as_str())))?;
    // openusd's matrices are row-major for row vectors: the same numbers, column-major, are the
    // column-vector matrix.
    let local = DMat4::from_cols_array(&local.0);
    let resets = prim.resets_xform_stack().unwrap_or(false);
    let parent = match path.parent() {
        Some(p) if !resets && p != sdf::Path::abs_root() => world_transform(stage, &p, cache)?,
        _ => DMat4::IDENTITY,
    };
    let world = parent * local;
    if !world.is_finite() {
        return Err(err(format!(
            "{}: the world transform is not finite",
            path.as_str()
        )));
    }
    cache.insert(path.as_str().to_string(), world);
    Ok(world)
}

fn merge_meshes(meshes: Vec<TriMesh>) -> Option<TriMesh> {
    match meshes.len() {
        1 => meshes.into_iter().find(|m| !m.indices.is_empty()),
        _ => TriMesh::merge(&meshes),
    }
}
