//! Writing an asset as one linear `BasisCurves` prim, `.usda` or `.usdc`, with openusd's
//! layer writers (see the [module docs](super)).

use openusd::sdf::{self, ChildrenKey, FieldKey, SpecType, Specifier, Value};
use openusd::{gf, usda, usdc};

use super::err;
use crate::{HairAsset, HairError};

/// Which USD encoding to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UsdFlavor {
    /// `.usda` text.
    Text,
    /// `.usdc` binary ("crate").
    Binary,
}

fn vec3f(v: glam::Vec3) -> gf::Vec3f {
    gf::Vec3f {
        x: v.x,
        y: v.y,
        z: v.z,
    }
}

/// The asset as a USD layer with one prim `/Hair` (linear `BasisCurves`).
pub fn write_usd(asset: &HairAsset, flavor: UsdFlavor) -> Result<Vec<u8>, HairError> {
    write_usd_frames(asset, None, flavor)
}

/// An animated cache: the asset (its counts, widths, colours) with `points` time-sampled, one
/// sample a frame at time codes 1, 2, … (`frames`, each as many vertices as the asset), and
/// the layer's `timeCodesPerSecond` and `framesPerSecond` set to `fps` and its start and end
/// time codes to the first and last frame.
pub fn write_usd_animated(
    asset: &HairAsset,
    frames: &[Vec<glam::Vec3>],
    fps: f64,
    flavor: UsdFlavor,
) -> Result<Vec<u8>, HairError> {
    write_usd_frames(asset, Some((frames, fps)), flavor)
}

fn points(p: &[glam::Vec3]) -> Value {
    Value::Vec3fVec(p.iter().map(|&p| vec3f(p)).collect())
}

fn write_usd_frames(
    asset: &HairAsset,
    animation: Option<(&[Vec<glam::Vec3>], f64)>,
    flavor: UsdFlavor,
) -> Result<Vec<u8>, HairError> {
    if let Some((frames, fps)) = animation {
        if frames.is_empty() {
            return Err(err("an animated cache needs at least one frame"));
        }
        crate::formats::check_frames(asset, frames, fps).map_err(err)?;
    }
    let counts = asset
        .vertex_counts()
        .map(i32::try_from)
        .collect::<Result<Vec<_>, _>>()
        .map_err(|_| err("a strand has more than 2^31 vertices"))?;
    let mut data = sdf::Data::new();
    let root = data.create_spec(sdf::Path::abs_root(), SpecType::PseudoRoot);
    root.add(
        ChildrenKey::PrimChildren,
        Value::TokenVec(vec!["Hair".into()]),
    );
    root.add(FieldKey::DefaultPrim, Value::Token("Hair".into()));
    root.add("upAxis", Value::Token("Y".into()));
    if let Some((frames, fps)) = animation {
        root.add(FieldKey::TimeCodesPerSecond, Value::Double(fps));
        root.add(FieldKey::FramesPerSecond, Value::Double(fps));
        root.add(FieldKey::StartTimeCode, Value::Double(1.0));
        root.add(FieldKey::EndTimeCode, Value::Double(frames.len() as f64));
    }

    let hair = sdf::path("/Hair").map_err(|e| err(format!("{e:#}")))?;
    let mut props: Vec<(&str, &str, Value, Option<&str>, bool)> = vec![
        (
            "curveVertexCounts",
            "int[]",
            Value::IntVec(counts),
            None,
            false,
        ),
        (
            "points",
            "point3f[]",
            points(asset.positions()),
            None,
            false,
        ),
        ("type", "token", Value::Token("linear".into()), None, true),
    ];
    if let Some(t) = asset.thickness() {
        props.push((
            "widths",
            "float[]",
            Value::FloatVec(t.to_vec()),
            Some("vertex"),
            false,
        ));
    }
    if let Some(c) = asset.color() {
        let v = Value::Vec3fVec(c.iter().map(|&p| vec3f(p)).collect());
        props.push((
            "primvars:displayColor",
            "color3f[]",
            v,
            Some("vertex"),
            false,
        ));
    }
    if let Some(t) = asset.transparency() {
        let v = Value::FloatVec(t.iter().map(|x| 1.0 - x).collect());
        props.push((
            "primvars:displayOpacity",
            "float[]",
            v,
            Some("vertex"),
            false,
        ));
    }
    if let Some(uv) = asset.strand_uv() {
        let v = Value::Vec2fVec(uv.iter().map(|p| gf::Vec2f { x: p.x, y: p.y }).collect());
        props.push(("primvars:st", "texCoord2f[]", v, Some("uniform"), false));
    }
    let spec = data.create_spec(hair.clone(), SpecType::Prim);
    spec.add(FieldKey::Specifier, Value::Specifier(Specifier::Def));
    spec.add(FieldKey::TypeName, Value::Token("BasisCurves".into()));
    spec.add(
        ChildrenKey::PropertyChildren,
        Value::TokenVec(props.iter().map(|p| p.0.into()).collect()),
    );
    for (name, type_name, value, interpolation, uniform) in props {
        let path = hair
            .append_property(name)
            .map_err(|e| err(format!("{e:#}")))?;
        let attr = data.create_spec(path, SpecType::Attribute);
        attr.add(FieldKey::TypeName, Value::Token(type_name.into()));
        match animation {
            Some((frames, _)) if name == "points" => {
                let samples = frames
                    .iter()
                    .enumerate()
                    .map(|(k, f)| ((k + 1) as f64, points(f)))
                    .collect();
                attr.add(FieldKey::TimeSamples, Value::TimeSamples(samples));
            }
            _ => attr.add(FieldKey::Default, value),
        }
        if uniform {
            attr.add(
                FieldKey::Variability,
                Value::Variability(sdf::Variability::Uniform),
            );
        }
        if let Some(i) = interpolation {
            attr.add("interpolation", Value::Token(i.into()));
        }
    }
    match flavor {
        UsdFlavor::Text => usda::TextWriter::write_to_string(&data)
            .map(String::into_bytes)
            .map_err(|e| err(format!("{e:#}"))),
        UsdFlavor::Binary => {
            let mut out = std::io::Cursor::new(Vec::new());
            usdc::CrateWriter::write(&data, &mut out).map_err(|e| err(format!("{e:#}")))?;
            Ok(out.into_inner())
        }
    }
}
