//! Alembic `.abc` (Ogawa) curves, read with the `tress-alembic` crate.
//!
//! Every `ICurves` object becomes strands in world space (its parent Xforms composed):
//! `P` and `nVertices`; the type and basis (linear, or cubic Bézier, B-spline and Catmull-Rom,
//! tessellated by the [rule of `curves`](super::curves); variable-order curves as NURBS);
//! `width` → thickness (its `geoScope` as the interpolation); and Unreal Engine's groom
//! attributes: `groom_color` → color, `groom_root_uv` → strand UV, and `groom_guide`: curves
//! with a non-zero value are simulation guides, not rendered hair, and are skipped (counted in
//! [`AbcInfo::guides_skipped`]). Other objects (meshes, cameras) and attributes are ignored; `P` is
//! read at [`ReadOptions::frame`] (an animated cache: [`AbcInfo::frames`] counts its samples and
//! [`AbcInfo::fps`] is their rate), everything else at its first sample. HDF5-based Alembic
//! files are refused: "HDF5 Alembic is not supported, re-export as Ogawa".

use glam::{DMat4, Vec2, Vec3};
use tress_alembic::{AlembicError, Basis, CurveType, Curves, Scope};

use super::curves::{CubicBasis, CurveSet, Interp, Primvar, ReadOptions, Shape, Wrap};
use crate::{HairAsset, HairError};

const FORMAT: &str = ".abc";

/// What a read found besides the strands.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AbcInfo {
    /// The curves objects read, by full name.
    pub objects: Vec<String>,
    /// Guide curves (`groom_guide` non-zero) left out.
    pub guides_skipped: usize,
    /// Objects of other schemas that were not read: full name and schema.
    pub ignored: Vec<(String, String)>,
    /// Frames of an animated cache: the most samples `P` has over the curves objects (1 for a
    /// still file; 0 only in a default value, never from a read).
    pub frames: u32,
    /// Frames a second of an animated cache: one over the seconds between samples of the
    /// object's `P` with the most (its time sampling); `None` for a still file.
    pub fps: Option<f64>,
}

fn error(e: AlembicError) -> HairError {
    HairError::format(FORMAT, e.to_string())
}

fn interp(scope: Scope) -> Option<Interp> {
    match scope {
        Scope::Constant => Some(Interp::Constant),
        Scope::Uniform => Some(Interp::Uniform),
        Scope::Varying | Scope::FaceVarying => Some(Interp::Varying),
        Scope::Vertex => Some(Interp::Vertex),
        Scope::Unknown => None,
    }
}

fn curve_set(mut c: Curves, guides: &mut usize) -> Result<CurveSet, HairError> {
    let name = c.path.clone();
    let shape = match (c.kind, c.basis) {
        (CurveType::Linear, _) => Shape::Linear,
        (CurveType::Cubic, b) => {
            let basis = match b {
                Basis::Bezier => CubicBasis::Bezier,
                Basis::Bspline => CubicBasis::Bspline,
                Basis::CatmullRom => CubicBasis::CatmullRom,
                other => {
                    return Err(HairError::format(
                        FORMAT,
                        format!("{name}: the {other:?} basis is not supported"),
                    ));
                }
            };
            let wrap = match c.wrap {
                tress_alembic::Wrap::NonPeriodic => Wrap::NonPeriodic,
                tress_alembic::Wrap::Periodic => Wrap::Periodic,
            };
            Shape::Cubic(basis, wrap)
        }
        (CurveType::VariableOrder, _) => {
            let orders = c.orders.take().unwrap_or_default();
            if orders.len() != c.vertex_counts.len() {
                return Err(HairError::format(
                    FORMAT,
                    format!(
                        "{name}: {} orders for {} curves",
                        orders.len(),
                        c.vertex_counts.len()
                    ),
                ));
            }
            Shape::Nurbs {
                orders: orders.into_iter().map(u32::from).collect(),
                knots: c
                    .knots
                    .take()
                    .unwrap_or_default()
                    .into_iter()
                    .map(f64::from)
                    .collect(),
                weights: c
                    .weights
                    .take()
                    .map(|w| w.into_iter().map(f64::from).collect()),
            }
        }
    };
    let curves = c.vertex_counts.len();
    let skip = match &c.guide {
        Some(g) => {
            let flags: Vec<bool> = match g.values.len() {
                1 => vec![g.values[0] != 0; curves],
                n if n == curves => g.values.iter().map(|&v| v != 0).collect(),
                n => {
                    return Err(HairError::format(
                        FORMAT,
                        format!("{name}: groom_guide has {n} values for {curves} curves"),
                    ));
                }
            };
            *guides += flags.iter().filter(|&&f| f).count();
            Some(flags)
        }
        None => None,
    };
    let strand_uv = match &c.root_uv {
        Some(p) if p.values.len() == curves => {
            Some(p.values.iter().map(|&v| Vec2::from_array(v)).collect())
        }
        Some(p) if p.values.len() == 1 => Some(vec![Vec2::from_array(p.values[0]); curves]),
        Some(p) => {
            return Err(HairError::format(
                FORMAT,
                format!(
                    "{name}: groom_root_uv has {} values for {curves} curves",
                    p.values.len()
                ),
            ));
        }
        None => None,
    };
    Ok(CurveSet {
        name,
        // `[f32; 3]` and `Vec3` have one layout: the array is handed over, not copied.
        positions: bytemuck::allocation::try_cast_vec(c.positions)
            .unwrap_or_else(|(_, p)| p.into_iter().map(Vec3::from_array).collect()),
        counts: c.vertex_counts,
        shape,
        widths: c.widths.map(|w| Primvar {
            interp: interp(w.scope),
            values: w.values,
        }),
        colors: c.colors.map(|p| Primvar {
            interp: interp(p.scope),
            values: p.values.into_iter().map(Vec3::from_array).collect(),
        }),
        opacity: None,
        strand_uv,
        skip,
        world: DMat4::from_cols_array(&c.world),
    })
}

/// Read the curves of an Ogawa Alembic file (see the [module docs](self)).
pub fn read_abc(bytes: &[u8], options: &ReadOptions) -> Result<(HairAsset, AbcInfo), HairError> {
    let contents = tress_alembic::read_frame(bytes, options.frame).map_err(error)?;
    let mut info = AbcInfo {
        ignored: contents.ignored,
        frames: 1,
        ..AbcInfo::default()
    };
    let mut assets = Vec::new();
    for c in contents.curves {
        info.objects.push(c.path.clone());
        if c.position_samples > info.frames {
            info.frames = c.position_samples;
            info.fps = c
                .seconds_per_position_sample
                .map(|s| 1.0 / s)
                .filter(|f| f.is_finite());
        }
        let set = curve_set(c, &mut info.guides_skipped)?;
        if let Some(a) = set.into_asset(options).map_err(in_format)? {
            assets.push(a);
        }
    }
    if assets.is_empty() {
        return Err(HairError::format(
            FORMAT,
            if info.objects.is_empty() {
                "the file has no curves (ICurves) objects".to_string()
            } else {
                format!(
                    "the curves objects {} hold only guides",
                    info.objects.join(", ")
                )
            },
        ));
    }
    Ok((HairAsset::merge_owned(assets).map_err(in_format)?, info))
}

fn in_format(e: HairError) -> HairError {
    match e {
        HairError::Invalid(reason) => HairError::format(FORMAT, reason),
        other => other,
    }
}

/// The asset as an Alembic (Ogawa) file: one linear `ICurves` object `hair` with `P`,
/// `nVertices` and, when the asset has them, `width` and `groom_color` per vertex. With more
/// than one frame (each as many vertices as the asset) `P` is an animated cache: one sample a
/// frame, `1 / fps` seconds apart from `1 / fps` (frame 1 in Blender), which Blender and the
/// Alembic library read as animated curves.
pub fn write_abc(asset: &HairAsset, frames: &[Vec<Vec3>], fps: f64) -> Result<Vec<u8>, HairError> {
    super::check_frames(asset, frames, fps).map_err(|reason| HairError::format(FORMAT, reason))?;
    let counts = asset
        .vertex_counts()
        .map(i32::try_from)
        .collect::<Result<Vec<_>, _>>()
        .map_err(|_| HairError::format(FORMAT, "a strand has more than 2^31 vertices"))?;
    let array = |p: &[Vec3]| p.iter().map(|v| v.to_array()).collect::<Vec<_>>();
    let (first, rest) = match frames.split_first() {
        Some((f, rest)) => (array(f), rest),
        None => (array(asset.positions()), &[][..]),
    };
    let curves = tress_alembic::write::CurvesOut {
        name: "hair".into(),
        positions: first,
        vertex_counts: counts,
        widths: asset
            .thickness()
            .map(|t| (tress_alembic::Scope::Vertex, t.to_vec())),
        colors: asset
            .color()
            .map(|c| (tress_alembic::Scope::Vertex, array(c))),
        frames: rest.iter().map(|f| array(f)).collect(),
        ..Default::default()
    };
    Ok(tress_alembic::write::write_animated(
        &[curves],
        tress_alembic::write::TimeSampling {
            seconds_per_frame: 1.0 / fps,
            start: 1.0 / fps,
        },
    ))
}
