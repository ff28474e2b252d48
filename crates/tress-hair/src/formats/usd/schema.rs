//! The schemas tress reads (`BasisCurves`, `NurbsCurves`, `Mesh`), from any source of
//! attribute values: the composed stage ([`Prim`]) or one layer read directly
//! ([`layer`](super::layer)). Both go through this one file, so the two reading paths cannot
//! interpret a prim differently.

use glam::{DMat4, Vec2, Vec3};
use openusd::sdf::Value;
use openusd::usd::{Prim, TimeCode};

use super::err;
use crate::HairError;
use crate::formats::curves::{CubicBasis, CurveSet, Interp, Primvar, Shape, Wrap};
use crate::generate::TriMesh;

/// A prim's attributes, however they are resolved.
pub(super) trait Attrs {
    /// The prim's path, for messages.
    fn prim_path(&self) -> &str;
    /// Attribute `name`'s value: its default, else its earliest time sample.
    fn value(&self, name: &str) -> Result<Option<Value>, HairError>;
    /// Attribute `name`'s `interpolation` metadata, if any (unreadable counts as none).
    fn interpolation(&self, name: &str) -> Option<Value>;
}

/// A stage prim read at a frame: `points` at its `frame`-th time sample (clamped to the last),
/// everything else as [`Prim`] reads it.
pub(super) struct AtFrame<'p> {
    pub(super) prim: &'p Prim,
    pub(super) frame: u32,
}

impl Attrs for AtFrame<'_> {
    fn prim_path(&self) -> &str {
        self.prim.prim_path()
    }

    fn value(&self, name: &str) -> Result<Option<Value>, HairError> {
        if self.frame == 0 || name != "points" {
            return self.prim.value(name);
        }
        let times = point_times(self.prim)?;
        match times.get((self.frame as usize).min(times.len().max(1) - 1)) {
            Some(&t) => self
                .prim
                .attribute(name)
                .get_at::<Value>(TimeCode::new(t))
                .map_err(|e| err(format!("{}.{name}: {e:#}", self.prim.path().as_str()))),
            None => self.prim.value(name),
        }
    }

    fn interpolation(&self, name: &str) -> Option<Value> {
        self.prim.interpolation(name)
    }
}

/// The time codes of a stage prim's `points` time samples (ascending; empty when it has none):
/// the frames [`AtFrame`] picks from.
pub(super) fn point_times(prim: &Prim) -> Result<Vec<f64>, HairError> {
    prim.attribute("points")
        .time_sample_times()
        .map_err(|e| err(format!("{}.points: {e:#}", prim.path().as_str())))
}

impl Attrs for Prim {
    fn prim_path(&self) -> &str {
        self.path().as_str()
    }

    fn value(&self, name: &str) -> Result<Option<Value>, HairError> {
        let attr = self.attribute(name);
        let where_ = || format!("{}.{name}", self.path().as_str());
        match attr.get::<Value>() {
            Ok(Some(v)) => Ok(Some(v)),
            Ok(None) => attr
                .get_at::<Value>(TimeCode::EARLIEST)
                .map_err(|e| err(format!("{}: {e:#}", where_()))),
            Err(e) => Err(err(format!("{}: {e:#}", where_()))),
        }
    }

    fn interpolation(&self, name: &str) -> Option<Value> {
        self.attribute(name)
            .get_metadata::<Value>("interpolation")
            .ok()
            .flatten()
    }
}

fn token(prim: &impl Attrs, name: &str) -> Result<Option<String>, HairError> {
    Ok(match prim.value(name)? {
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

fn interp_of(prim: &impl Attrs, name: &str) -> Option<Interp> {
    match prim.interpolation(name) {
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
    prim: &impl Attrs,
    name: &str,
    convert: impl Fn(Value, &str) -> Result<Vec<T>, HairError>,
) -> Result<Option<Primvar<T>>, HairError> {
    let where_ = format!("{}.{name}", prim.prim_path());
    let Some(v) = prim.value(name)? else {
        return Ok(None);
    };
    let mut values = convert(v, &where_)?;
    if let Some(idx) = prim.value(&format!("{name}:indices"))? {
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

fn counts(prim: &impl Attrs, name: &str, what: &str) -> Result<Vec<u32>, HairError> {
    let v = prim
        .value(name)?
        .ok_or_else(|| err(format!("{what} has no {name}")))?;
    ints(v, what)?
        .into_iter()
        .enumerate()
        .map(|(i, c)| u32::try_from(c).map_err(|_| err(format!("{what}: {name}[{i}] is {c}"))))
        .collect()
}

pub(super) fn curve_set(
    prim: &impl Attrs,
    ty: &str,
    path: &str,
    world: DMat4,
) -> Result<CurveSet, HairError> {
    let counts = counts(prim, "curveVertexCounts", path)?;
    let positions = match prim.value("points")? {
        Some(v) => vec3s(v, &format!("{path}.points"))?,
        None => return Err(err(format!("{path} has no points"))),
    };
    let shape = if ty == "NurbsCurves" {
        let orders = counts_or_empty(prim, "order", path)?;
        let knots = match prim.value("knots")? {
            Some(v) => floats(v, &format!("{path}.knots"))?,
            None => Vec::new(),
        };
        let weights = match prim.value("pointWeights")? {
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

fn counts_or_empty(prim: &impl Attrs, name: &str, path: &str) -> Result<Vec<u32>, HairError> {
    match prim.value(name)? {
        Some(_) => counts(prim, name, path),
        None => Ok(Vec::new()),
    }
}

/// A `Mesh` prim fan-triangulated in world space (normals from the faces).
pub(super) fn mesh(prim: &impl Attrs, path: &str, world: DMat4) -> Result<TriMesh, HairError> {
    let positions = match prim.value("points")? {
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
