//! The two schemas tress reads: `AbcGeom_Xform` (object transforms) and `AbcGeom_Curve`
//! (`ICurves`), plus the walk over the object tree that composes world transforms.
//!
//! # Xform
//!
//! An Xform object's `.xform` compound holds `.ops` (one `u8` per operation: type in the high
//! nibble, hint in the low one), `.vals` (the `f64` channels of all operations in order) and
//! `.inherits` (absent or true: the parent's transform applies). Operation types and channel
//! counts (`AbcGeom/XformOp.h`): 0 scale (3), 1 translate (3), 2 rotate (axis xyz, angle in
//! degrees), 3 matrix (16, Imath row-major), 4 / 5 / 6 rotate about x / y / z (angle in degrees).
//! As in `XformSample::getMatrix`, the first operation is the outermost: for column vectors the
//! local matrix is `op0 · op1 · … · opn`, and an object's world matrix is its parent's world
//! matrix times its local matrix.
//!
//! # Curves
//!
//! A Curve object's `.geom` compound: `P` (`float32[3]` per vertex), `nVertices` (`int32` per
//! curve), `curveBasisAndType` (`u8[4]`: type 0 cubic, 1 linear, 2 variable order; wrap 0
//! non-periodic, 1 periodic; basis 0 none, 1 Bezier, 2 B-spline, 3 Catmull-Rom, 4 Hermite,
//! 5 power), and optionally `width` (a geometry parameter), `w` (position weights), `.orders`
//! (`u8` per curve) and `.knots` (`float32`) for variable-order (NURBS) curves, and
//! `.arbGeomParams` holding user parameters. Of those, Unreal Engine's groom attributes are read:
//! `groom_color` (`float32[3]`), `groom_root_uv` (`float32[2]`) and `groom_guide` (an integer:
//! non-zero marks a simulation guide). A geometry parameter is either an array property or, when
//! indexed, a compound of `.vals` and `.indices`; its `geoScope` metadata (`con`, `uni`, `var`,
//! `vtx`, `fvr`) says what its values are attached to.

use std::borrow::Cow;

use crate::archive::{Compound, Kind, Pod, Reader, meta_value};
use crate::ogawa::Group;
use crate::{AlembicError, Basis, CurveType, Curves, Param, Scope, Wrap};

fn malformed(reason: impl Into<String>) -> AlembicError {
    AlembicError::Malformed(reason.into())
}

/// A column-major 4×4 matrix for column vectors.
pub(crate) type Mat4 = [f64; 16];

/// The identity matrix.
pub(crate) const IDENTITY: Mat4 = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    let mut out = [0.0; 16];
    for c in 0..4 {
        for r in 0..4 {
            out[c * 4 + r] = (0..4).map(|k| a[k * 4 + r] * b[c * 4 + k]).sum();
        }
    }
    out
}

fn rotation(axis: [f64; 3], degrees: f64) -> Mat4 {
    let len = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    if len == 0.0 || !len.is_finite() {
        return IDENTITY;
    }
    let [x, y, z] = axis.map(|v| v / len);
    let (s, c) = degrees.to_radians().sin_cos();
    let t = 1.0 - c;
    [
        t * x * x + c,
        t * x * y + s * z,
        t * x * z - s * y,
        0.0,
        t * x * y - s * z,
        t * y * y + c,
        t * y * z + s * x,
        0.0,
        t * x * z + s * y,
        t * y * z - s * x,
        t * z * z + c,
        0.0,
        0.0,
        0.0,
        0.0,
        1.0,
    ]
}

/// The local matrix of an Xform object's `.xform` compound, and whether it inherits.
fn xform<'a>(reader: &mut Reader<'a>, props: &Compound<'a>) -> Result<(Mat4, bool), AlembicError> {
    let Some(x) = reader.sub_compound(props, ".xform")? else {
        return Ok((IDENTITY, true));
    };
    let inherits = match Reader::find(&x, ".inherits") {
        Some((i, _)) => reader.first_sample(&x, i)?.first().is_none_or(|&b| b != 0),
        None => true,
    };
    let ops = match Reader::find(&x, ".ops") {
        Some((i, _)) => reader.first_sample(&x, i)?.to_vec(),
        None => Vec::new(),
    };
    let vals = match Reader::find(&x, ".vals") {
        Some((i, h)) if h.pod == Pod::F64 => f64s(reader.first_sample(&x, i)?),
        Some((_, h)) => {
            return Err(malformed(format!(
                ".xform/.vals is {:?}, not float64",
                h.pod
            )));
        }
        None => Vec::new(),
    };
    let mut m = IDENTITY;
    let mut at = 0;
    for &op in &ops {
        let channels = match op >> 4 {
            0 | 1 => 3,
            2 => 4,
            3 => 16,
            4..=6 => 1,
            other => return Err(malformed(format!("unknown transform operation {other}"))),
        };
        let ch = |k: usize, default: f64| vals.get(at + k).copied().unwrap_or(default);
        let local = match op >> 4 {
            0 => {
                let mut s = IDENTITY;
                (s[0], s[5], s[10]) = (ch(0, 1.0), ch(1, 1.0), ch(2, 1.0));
                s
            }
            1 => {
                let mut t = IDENTITY;
                (t[12], t[13], t[14]) = (ch(0, 0.0), ch(1, 0.0), ch(2, 0.0));
                t
            }
            2 => rotation([ch(0, 0.0), ch(1, 0.0), ch(2, 1.0)], ch(3, 0.0)),
            3 => std::array::from_fn(|k| ch(k, IDENTITY[k])),
            4 => rotation([1.0, 0.0, 0.0], ch(0, 0.0)),
            5 => rotation([0.0, 1.0, 0.0], ch(0, 0.0)),
            _ => rotation([0.0, 0.0, 1.0], ch(0, 0.0)),
        };
        m = mul(&m, &local);
        at += channels;
    }
    if m.iter().any(|v| !v.is_finite()) {
        return Err(malformed("an Xform's matrix is not finite"));
    }
    Ok((m, inherits))
}

/// Walk the object tree below `object`, collecting every Curve object with its world matrix.
pub(crate) fn walk<'a>(
    reader: &mut Reader<'a>,
    object: Group<'a>,
    path: &str,
    world: Mat4,
    depth: usize,
    out: &mut crate::Contents,
) -> Result<(), AlembicError> {
    if depth > crate::archive::MAX_DEPTH {
        return Err(malformed(format!(
            "objects nest deeper than {} levels",
            crate::archive::MAX_DEPTH
        )));
    }
    for (header, group) in reader.children(&object)? {
        let child_path = format!("{path}/{}", header.name);
        let schema = meta_value(&header.metadata, "schema").unwrap_or("");
        let props = reader.properties(&group)?;
        let mut child_world = world;
        if schema.starts_with("AbcGeom_Xform") {
            if let Some(props) = &props {
                let (local, inherits) = xform(reader, props)?;
                child_world = if inherits { mul(&world, &local) } else { local };
            }
        } else if schema.starts_with("AbcGeom_Curve") {
            let props =
                props.ok_or_else(|| malformed(format!("{child_path} has no properties")))?;
            out.curves
                .push(curves(reader, &props, child_path.clone(), world)?);
        } else if !schema.is_empty() {
            out.ignored.push((child_path.clone(), schema.to_string()));
        }
        walk(reader, group, &child_path, child_world, depth + 1, out)?;
    }
    Ok(())
}

fn f32s(bytes: &[u8]) -> Vec<f32> {
    bytes
        .as_chunks::<4>()
        .0
        .iter()
        .map(|w| f32::from_le_bytes(*w))
        .collect()
}

/// Little-endian `[f32; N]`s in one pass (a trailing partial element is ignored).
fn f32_arrays<const N: usize>(bytes: &[u8]) -> Vec<[f32; N]> {
    let words = bytes.as_chunks::<4>().0;
    words
        .as_chunks::<N>()
        .0
        .iter()
        .map(|e| e.map(f32::from_le_bytes))
        .collect()
}

fn f64s(bytes: &[u8]) -> Vec<f64> {
    bytes
        .as_chunks::<8>()
        .0
        .iter()
        .map(|w| f64::from_le_bytes(*w))
        .collect()
}

/// Integers of any integer POD, widened.
fn ints(pod: Pod, bytes: &[u8], name: &str) -> Result<Vec<i64>, AlembicError> {
    Ok(match pod {
        Pod::Bool | Pod::U8 => bytes.iter().map(|&b| i64::from(b)).collect(),
        Pod::I8 => bytes.iter().map(|&b| i64::from(b as i8)).collect(),
        Pod::U16 => bytes
            .as_chunks::<2>()
            .0
            .iter()
            .map(|w| i64::from(u16::from_le_bytes(*w)))
            .collect(),
        Pod::I16 => bytes
            .as_chunks::<2>()
            .0
            .iter()
            .map(|w| i64::from(i16::from_le_bytes(*w)))
            .collect(),
        Pod::U32 => bytes
            .as_chunks::<4>()
            .0
            .iter()
            .map(|w| i64::from(u32::from_le_bytes(*w)))
            .collect(),
        Pod::I32 => bytes
            .as_chunks::<4>()
            .0
            .iter()
            .map(|w| i64::from(i32::from_le_bytes(*w)))
            .collect(),
        Pod::U64 | Pod::I64 => bytes
            .as_chunks::<8>()
            .0
            .iter()
            .map(|w| i64::from_le_bytes(*w))
            .collect(),
        other => return Err(malformed(format!("{name} is {other:?}, not an integer"))),
    })
}

fn scope_of(metadata: &str) -> Scope {
    match meta_value(metadata, "geoScope") {
        Some("con") => Scope::Constant,
        Some("uni") => Scope::Uniform,
        Some("var") => Scope::Varying,
        Some("vtx") => Scope::Vertex,
        Some("fvr") => Scope::FaceVarying,
        _ => Scope::Unknown,
    }
}

/// A geometry parameter's scope and the bytes of its values.
type RawParam<'a> = (Scope, Cow<'a, [u8]>);

/// The raw values of a geometry parameter (`extent` numbers per element, as bytes of `pod`),
/// expanded through its indices when it is indexed (otherwise borrowed from the file), with its
/// scope.
fn geom_param<'a>(
    reader: &mut Reader<'a>,
    parent: &Compound<'a>,
    name: &str,
    pod: Pod,
    extent: usize,
) -> Result<Option<RawParam<'a>>, AlembicError> {
    let Some((index, header)) = Reader::find(parent, name) else {
        return Ok(None);
    };
    let header = header.clone();
    let element = pod.size().unwrap_or(1) * extent;
    let check = |h: &crate::archive::PropertyHeader| {
        if h.pod != pod || h.extent != extent {
            Err(malformed(format!(
                "{name} is {:?}[{}], not {pod:?}[{extent}]",
                h.pod, h.extent
            )))
        } else {
            Ok(())
        }
    };
    match header.kind {
        Kind::Array | Kind::Scalar => {
            check(&header)?;
            let bytes = reader.first_sample(parent, index)?;
            Ok(Some((scope_of(&header.metadata), Cow::Borrowed(bytes))))
        }
        Kind::Compound => {
            let c = reader
                .sub_compound(parent, name)?
                .ok_or_else(|| malformed(format!("{name} vanished")))?;
            let (vi, vh) = Reader::find(&c, ".vals")
                .ok_or_else(|| malformed(format!("indexed {name} has no .vals")))?;
            check(vh)?;
            let vals = reader.first_sample(&c, vi)?;
            let count = vals.len() / element;
            let out =
                match Reader::find(&c, ".indices") {
                    Some((ii, ih)) => {
                        let ipod = ih.pod;
                        let idx = ints(ipod, reader.first_sample(&c, ii)?, name)?;
                        let mut out = Vec::with_capacity(idx.len() * element);
                        for i in idx {
                            let i = usize::try_from(i).ok().filter(|&i| i < count).ok_or_else(
                                || {
                                    malformed(format!(
                                        "{name}: index {i} is past its {count} values"
                                    ))
                                },
                            )?;
                            out.extend_from_slice(&vals[i * element..(i + 1) * element]);
                        }
                        Cow::Owned(out)
                    }
                    None => Cow::Borrowed(vals),
                };
            Ok(Some((scope_of(&header.metadata), out)))
        }
    }
}

fn param_f32<'a>(
    reader: &mut Reader<'a>,
    parent: &Compound<'a>,
    name: &str,
) -> Result<Option<Param<f32>>, AlembicError> {
    Ok(
        geom_param(reader, parent, name, Pod::F32, 1)?.map(|(scope, b)| Param {
            scope,
            values: f32s(&b),
        }),
    )
}

fn param_f32n<'a, const N: usize>(
    reader: &mut Reader<'a>,
    parent: &Compound<'a>,
    name: &str,
) -> Result<Option<Param<[f32; N]>>, AlembicError> {
    Ok(
        geom_param(reader, parent, name, Pod::F32, N)?.map(|(scope, b)| Param {
            scope,
            values: f32_arrays::<N>(&b),
        }),
    )
}

/// A Curve object: `P` at the reader's frame, everything else at its first sample.
fn curves<'a>(
    reader: &mut Reader<'a>,
    props: &Compound<'a>,
    path: String,
    world: Mat4,
) -> Result<Curves, AlembicError> {
    let geom = reader
        .sub_compound(props, ".geom")?
        .ok_or_else(|| malformed(format!("{path} has no .geom")))?;
    let required = |name: &str| {
        Reader::find(&geom, name)
            .map(|(i, h)| (i, h.clone()))
            .ok_or_else(|| malformed(format!("{path} has no {name}")))
    };
    let (pi, ph) = required("P")?;
    if ph.pod != Pod::F32 || ph.extent != 3 || ph.kind != Kind::Array {
        return Err(malformed(format!("{path}/P is not an array of float32[3]")));
    }
    let frame = reader.frame;
    let positions = f32_arrays::<3>(reader.sample(&geom, pi, frame)?);
    let position_samples = ph.samples.max(1);
    let seconds_per_position_sample = reader
        .time_samplings
        .get(ph.time_sampling as usize)
        .and_then(|t| t.seconds_per_sample())
        .filter(|_| position_samples > 1);
    let (ni, nh) = required("nVertices")?;
    let counts = ints(nh.pod, reader.first_sample(&geom, ni)?, "nVertices")?;
    let mut total: u64 = 0;
    let mut vertex_counts = Vec::with_capacity(counts.len());
    for (i, &c) in counts.iter().enumerate() {
        let c = u32::try_from(c)
            .map_err(|_| malformed(format!("{path}: curve {i} has {c} vertices")))?;
        total += u64::from(c);
        vertex_counts.push(c);
    }
    if total != positions.len() as u64 {
        return Err(malformed(format!(
            "{path}: nVertices adds up to {total} vertices but P holds {}",
            positions.len()
        )));
    }
    let (kind, wrap, basis) = match Reader::find(&geom, "curveBasisAndType") {
        Some((i, _)) => {
            let b = reader.first_sample(&geom, i)?;
            let get = |k: usize| b.get(k).copied().unwrap_or(0);
            let kind = match get(0) {
                0 => CurveType::Cubic,
                1 => CurveType::Linear,
                2 => CurveType::VariableOrder,
                other => return Err(malformed(format!("{path}: unknown curve type {other}"))),
            };
            let wrap = if get(1) == 1 {
                Wrap::Periodic
            } else {
                Wrap::NonPeriodic
            };
            let basis = match get(2) {
                0 => Basis::None,
                1 => Basis::Bezier,
                2 => Basis::Bspline,
                3 => Basis::CatmullRom,
                4 => Basis::Hermite,
                5 => Basis::Power,
                other => return Err(malformed(format!("{path}: unknown curve basis {other}"))),
            };
            (kind, wrap, basis)
        }
        None => (CurveType::Linear, Wrap::NonPeriodic, Basis::None),
    };
    let widths = param_f32(reader, &geom, "width")?;
    let weights = param_f32(reader, &geom, "w")?
        .map(|p| p.values)
        .filter(|w| !w.is_empty());
    let orders = match Reader::find(&geom, ".orders") {
        Some((i, h)) => {
            let h = h.clone();
            Some(ints(h.pod, reader.first_sample(&geom, i)?, ".orders")?)
        }
        None => None,
    }
    .filter(|o| !o.is_empty())
    .map(|o| o.into_iter().map(|v| v.clamp(0, 255) as u8).collect());
    let knots = param_f32(reader, &geom, ".knots")?
        .map(|p| p.values)
        .filter(|k| !k.is_empty());
    let (mut colors, mut root_uv, mut guide) = (None, None, None);
    if let Some(arb) = reader.sub_compound(&geom, ".arbGeomParams")? {
        colors = param_f32n::<3>(reader, &arb, "groom_color")?;
        root_uv = param_f32n::<2>(reader, &arb, "groom_root_uv")?;
        if let Some((i, h)) = Reader::find(&arb, "groom_guide") {
            let h = h.clone();
            let values = match h.kind {
                Kind::Compound => {
                    return Err(malformed(format!(
                        "{path}: indexed groom_guide is not supported"
                    )));
                }
                _ => ints(h.pod, reader.first_sample(&arb, i)?, "groom_guide")?,
            };
            guide = Some(Param {
                scope: scope_of(&h.metadata),
                values,
            });
        }
    }
    Ok(Curves {
        path,
        world,
        positions,
        vertex_counts,
        kind,
        wrap,
        basis,
        widths,
        weights,
        orders,
        knots,
        colors,
        root_uv,
        guide,
        position_samples,
        seconds_per_position_sample,
    })
}
