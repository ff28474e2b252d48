//! USD (`.usda`, `.usdc`, `.usdz`) curves and meshes, read and written with the `openusd` crate.
//!
//! # Reading
//!
//! The stage is opened and composed (references, payloads, sublayers, variants) and every
//! active prim is visited:
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
//! Attributes with only time samples are read at the earliest one. Everything else (materials,
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

mod memory;
mod usdc_check;
mod write;

use std::collections::HashMap;
use std::path::Path;

use glam::{DMat4, Vec2, Vec3};
use openusd::schemas::geom::{Imageable, Xformable};
use openusd::sdf::{self, Value};
use openusd::usd::{Prim, PrimPredicate, SchemaBase, SchemaKind, Stage, TimeCode};

use memory::MemoryResolver;

use super::curves::{CubicBasis, CurveSet, Interp, Primvar, ReadOptions, Shape, Wrap};
use crate::generate::TriMesh;
use crate::{HairAsset, HairError};

pub use write::{UsdFlavor, write_usd};

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
    guarded(|| {
        let stage = Stage::open(name).map_err(|e| err(format!("{e:#}")))?;
        contents(&stage, options)
    })
}

/// Run openusd, turning a panic inside it (it has `todo!()`s on some malformed inputs) into an
/// error.
fn guarded<T>(f: impl FnOnce() -> Result<T, HairError>) -> Result<T, HairError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(err(format!("openusd could not read the file ({what})")))
    })
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
    let name = format!("memory.{extension}");
    if extension == "usdc" {
        if !bytes.starts_with(b"PXR-USDC") {
            return Err(err(format!(
                "not a .usdc file: it starts with \"{}\" instead of \"PXR-USDC\"",
                bytes[..bytes.len().min(8)].escape_ascii()
            )));
        }
        usdc_check::check(bytes).map_err(err)?;
    }
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
    let Some(order) = prim
        .xform_op_order()
        .map_err(|e| err(format!("{path}: {e:#}")))?
    else {
        return Ok(());
    };
    for op in &order {
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

fn contents(stage: &Stage, options: &ReadOptions) -> Result<UsdContents, HairError> {
    check_hierarchy(stage)?;
    let mut paths = Vec::new();
    stage
        .traverse(PrimPredicate::DEFAULT, |p| paths.push(p.clone()))
        .map_err(|e| err(format!("{e:#}")))?;
    let mut worlds: HashMap<String, DMat4> = HashMap::new();
    let mut assets = Vec::new();
    let mut meshes = Vec::new();
    let mut info = UsdInfo::default();
    for path in &paths {
        let prim = stage.prim(path.clone());
        let ty = prim.type_name().map_err(|e| err(format!("{e:#}")))?;
        let ty = ty.as_ref().map(|t| t.as_str()).unwrap_or("");
        if !matches!(ty, "BasisCurves" | "NurbsCurves" | "Mesh") {
            continue;
        }
        let world = world_transform(stage, path, &mut worlds)?;
        let where_ = path.as_str().to_string();
        if ty == "Mesh" {
            meshes.push(mesh(&prim, &where_, world)?);
            info.meshes.push(where_);
            continue;
        }
        let set = curve_set(&prim, ty, &where_, world)?;
        info.prims.push(where_);
        if let Some(a) = set.into_asset(options).map_err(in_format)? {
            assets.push(a);
        }
    }
    if let Some(e) = stage.composition_errors().first() {
        return Err(err(format!("composition error: {e}")));
    }
    let hair = if assets.is_empty() {
        None
    } else {
        Some(HairAsset::merge_owned(assets).map_err(in_format)?)
    };
    let mesh = merge_meshes(meshes);
    Ok(UsdContents { hair, mesh, info })
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

/// An attribute's value: its default, else its earliest time sample.
fn value(prim: &Prim, name: &str) -> Result<Option<Value>, HairError> {
    let attr = prim.attribute(name);
    let where_ = || format!("{}.{name}", prim.path().as_str());
    match attr.get::<Value>() {
        Ok(Some(v)) => Ok(Some(v)),
        Ok(None) => attr
            .get_at::<Value>(TimeCode::EARLIEST)
            .map_err(|e| err(format!("{}: {e:#}", where_()))),
        Err(e) => Err(err(format!("{}: {e:#}", where_()))),
    }
}

fn token(prim: &Prim, name: &str) -> Result<Option<String>, HairError> {
    Ok(match value(prim, name)? {
        Some(Value::Token(t)) => Some(t.as_str().to_string()),
        Some(Value::String(s)) => Some(s),
        _ => None,
    })
}

fn ints(v: Value, what: &str) -> Result<Vec<i64>, HairError> {
    Ok(match v {
        Value::IntVec(v) => v.into_iter().map(i64::from).collect(),
        Value::UintVec(v) => v.into_iter().map(i64::from).collect(),
        Value::Int64Vec(v) => v,
        Value::Int(i) => vec![i64::from(i)],
        other => return Err(err(format!("{what} is {}, not integers", kind_of(&other)))),
    })
}

fn floats(v: Value, what: &str) -> Result<Vec<f64>, HairError> {
    Ok(match v {
        Value::FloatVec(v) => v.into_iter().map(f64::from).collect(),
        Value::DoubleVec(v) => v,
        Value::HalfVec(v) => v.into_iter().map(f64::from).collect(),
        Value::Float(f) => vec![f64::from(f)],
        Value::Double(f) => vec![f],
        other => return Err(err(format!("{what} is {}, not numbers", kind_of(&other)))),
    })
}

/// Numbers as `f32` (float arrays, the usual case, move as they are).
fn f32s(v: Value, what: &str) -> Result<Vec<f32>, HairError> {
    Ok(match v {
        Value::FloatVec(v) => v,
        other => floats(other, what)?.into_iter().map(|x| x as f32).collect(),
    })
}

fn vec3s(v: Value, what: &str) -> Result<Vec<Vec3>, HairError> {
    Ok(match v {
        // `gf::Vec3f` and `Vec3` have one layout: the array is handed over, not copied.
        Value::Vec3fVec(v) => bytemuck::allocation::try_cast_vec(v)
            .unwrap_or_else(|(_, v)| v.into_iter().map(|p| Vec3::new(p.x, p.y, p.z)).collect()),
        Value::Vec3dVec(v) => v
            .into_iter()
            .map(|p| Vec3::new(p.x as f32, p.y as f32, p.z as f32))
            .collect(),
        Value::Vec3hVec(v) => v
            .into_iter()
            .map(|p| Vec3::new(p.x.to_f32(), p.y.to_f32(), p.z.to_f32()))
            .collect(),
        other => return Err(err(format!("{what} is {}, not 3-vectors", kind_of(&other)))),
    })
}

fn kind_of(v: &Value) -> String {
    let s = format!("{v:?}");
    s.split(['(', ' ', '{'])
        .next()
        .unwrap_or("a value")
        .to_string()
}

fn interp_of(prim: &Prim, name: &str) -> Option<Interp> {
    let v = prim
        .attribute(name)
        .get_metadata::<Value>("interpolation")
        .ok()
        .flatten();
    match v {
        Some(Value::Token(t)) => match t.as_str() {
            "constant" => Some(Interp::Constant),
            "uniform" => Some(Interp::Uniform),
            "varying" | "faceVarying" => Some(Interp::Varying),
            "vertex" => Some(Interp::Vertex),
            _ => None,
        },
        _ => None,
    }
}

/// A primvar, expanded through `NAME:indices` when indexed.
fn primvar<T: Copy>(
    prim: &Prim,
    name: &str,
    convert: impl Fn(Value, &str) -> Result<Vec<T>, HairError>,
) -> Result<Option<Primvar<T>>, HairError> {
    let where_ = format!("{}.{name}", prim.path().as_str());
    let Some(v) = value(prim, name)? else {
        return Ok(None);
    };
    let mut values = convert(v, &where_)?;
    if let Some(idx) = value(prim, &format!("{name}:indices"))? {
        let idx = ints(idx, &where_)?;
        let n = values.len();
        values = idx
            .into_iter()
            .map(|i| {
                usize::try_from(i)
                    .ok()
                    .and_then(|i| values.get(i).copied())
                    .ok_or_else(|| err(format!("{where_}: index {i} is past its {n} values")))
            })
            .collect::<Result<_, _>>()?;
    }
    if values.is_empty() {
        return Ok(None);
    }
    Ok(Some(Primvar {
        interp: interp_of(prim, name),
        values,
    }))
}

fn counts(prim: &Prim, name: &str, what: &str) -> Result<Vec<u32>, HairError> {
    let v = value(prim, name)?.ok_or_else(|| err(format!("{what} has no {name}")))?;
    ints(v, what)?
        .into_iter()
        .enumerate()
        .map(|(i, c)| u32::try_from(c).map_err(|_| err(format!("{what}: {name}[{i}] is {c}"))))
        .collect()
}

fn curve_set(prim: &Prim, ty: &str, path: &str, world: DMat4) -> Result<CurveSet, HairError> {
    let counts = counts(prim, "curveVertexCounts", path)?;
    let positions = match value(prim, "points")? {
        Some(v) => vec3s(v, &format!("{path}.points"))?,
        None => return Err(err(format!("{path} has no points"))),
    };
    let shape = if ty == "NurbsCurves" {
        let orders = counts_or_empty(prim, "order", path)?;
        let knots = match value(prim, "knots")? {
            Some(v) => floats(v, &format!("{path}.knots"))?,
            None => Vec::new(),
        };
        let weights = match value(prim, "pointWeights")? {
            Some(v) => Some(floats(v, &format!("{path}.pointWeights"))?),
            None => None,
        };
        if orders.len() != counts.len() {
            return Err(err(format!(
                "{path}: {} orders for {} curves",
                orders.len(),
                counts.len()
            )));
        }
        Shape::Nurbs {
            orders,
            knots,
            weights,
        }
    } else {
        match token(prim, "type")?.as_deref().unwrap_or("cubic") {
            "linear" => Shape::Linear,
            "cubic" => {
                let basis = match token(prim, "basis")?.as_deref().unwrap_or("bezier") {
                    "bezier" => CubicBasis::Bezier,
                    "bspline" => CubicBasis::Bspline,
                    "catmullRom" => CubicBasis::CatmullRom,
                    other => return Err(err(format!("{path}: basis `{other}` is not supported"))),
                };
                let wrap = match token(prim, "wrap")?.as_deref().unwrap_or("nonperiodic") {
                    "nonperiodic" => Wrap::NonPeriodic,
                    "pinned" => Wrap::Pinned,
                    "periodic" => Wrap::Periodic,
                    other => return Err(err(format!("{path}: wrap `{other}` is not supported"))),
                };
                Shape::Cubic(basis, wrap)
            }
            other => {
                return Err(err(format!(
                    "{path}: type `{other}` is not linear or cubic"
                )));
            }
        }
    };
    let widths = match primvar(prim, "widths", f32s)? {
        Some(w) => Some(w),
        None => primvar(prim, "primvars:widths", f32s)?,
    };
    let colors = primvar(prim, "primvars:displayColor", vec3s)?;
    let opacity = primvar(prim, "primvars:displayOpacity", f32s)?;
    let strand_uv = match primvar(prim, "primvars:st", |v, w| {
        Ok(match v {
            Value::Vec2fVec(v) => v.into_iter().map(|p| Vec2::new(p.x, p.y)).collect(),
            Value::Vec2dVec(v) => v
                .into_iter()
                .map(|p| Vec2::new(p.x as f32, p.y as f32))
                .collect(),
            other => return Err(err(format!("{w} is {}, not 2-vectors", kind_of(&other)))),
        })
    })? {
        Some(st) if st.interp == Some(Interp::Uniform) && st.values.len() == counts.len() => {
            Some(st.values)
        }
        _ => None,
    };
    Ok(CurveSet {
        name: path.to_string(),
        positions,
        counts,
        shape,
        widths,
        colors,
        opacity,
        strand_uv,
        skip: None,
        world,
    })
}

fn counts_or_empty(prim: &Prim, name: &str, path: &str) -> Result<Vec<u32>, HairError> {
    match value(prim, name)? {
        Some(_) => counts(prim, name, path),
        None => Ok(Vec::new()),
    }
}

/// A `Mesh` prim fan-triangulated in world space (normals from the faces).
fn mesh(prim: &Prim, path: &str, world: DMat4) -> Result<TriMesh, HairError> {
    let positions = match value(prim, "points")? {
        Some(v) => vec3s(v, &format!("{path}.points"))?,
        None => return Err(err(format!("{path} has no points"))),
    };
    let face_counts = counts(prim, "faceVertexCounts", path)?;
    let indices = counts(prim, "faceVertexIndices", path)?;
    let left = token(prim, "orientation")?.as_deref() == Some("leftHanded");
    let flip = left != (world.determinant() < 0.0);
    let total: u64 = face_counts.iter().map(|&c| u64::from(c)).sum();
    if total != indices.len() as u64 {
        return Err(err(format!(
            "{path}: faceVertexCounts add up to {total} but there are {} indices",
            indices.len()
        )));
    }
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(err(format!(
            "{path}: face index {bad} is past its {} points",
            positions.len()
        )));
    }
    let mut tris = Vec::with_capacity(indices.len() * 3);
    let mut at = 0usize;
    for &c in &face_counts {
        let face = &indices[at..at + c as usize];
        at += c as usize;
        for k in 2..face.len() {
            if flip {
                tris.extend_from_slice(&[face[0], face[k], face[k - 1]]);
            } else {
                tris.extend_from_slice(&[face[0], face[k - 1], face[k]]);
            }
        }
    }
    let m = world.as_mat4();
    let positions: Vec<Vec3> = positions
        .into_iter()
        .map(|p| m.transform_point3(p))
        .collect();
    if positions.iter().any(|p| !p.is_finite()) {
        return Err(err(format!("{path}: a point is not finite")));
    }
    let normals = crate::patches::obj::face_normals(&positions, &tris);
    Ok(TriMesh {
        positions,
        normals,
        indices: tris,
    })
}

fn merge_meshes(meshes: Vec<TriMesh>) -> Option<TriMesh> {
    let mut iter = meshes.into_iter().filter(|m| !m.indices.is_empty());
    let mut out = iter.next()?;
    for m in iter {
        let base = out.positions.len() as u32;
        out.positions.extend(m.positions);
        out.normals.extend(m.normals);
        out.indices.extend(m.indices.iter().map(|i| i + base));
    }
    Some(out)
}
