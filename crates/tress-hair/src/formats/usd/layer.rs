//! The direct path for a `.usdc` file: its one layer read without a [`Stage`](openusd::usd::Stage).
//!
//! A groom exported as one crate file with no composition arcs composes to exactly what its
//! layer says, so tress can walk the layer's prim specs itself instead of building a stage:
//! openusd's stage copies the file and reads the whole layer twice (once for its expression
//! variables), which made a 136k-strand groom 10× slower to read than the same strands as
//! `.hair`. Here openusd's crate reader runs on the caller's bytes as they are (a borrowed
//! cursor, no copy), once.
//!
//! The walk reproduces the stage's default traversal on a single layer: children in
//! `primChildren` order, depth first; a prim is visited when it is `def` and not `active = false`,
//! and a prim that is not (an `over`, a `class`, an inactive prim, a child with no spec) hides its
//! subtree. Attribute values are the authored `default`; `xformOp`s compose as openusd's
//! `Xformable` composes them (the same `gf` matrices, in the same order).
//!
//! Anything this path does not model sends the read back to the stage, so results never differ:
//! a layer field outside [`ROOT_FIELDS`], a prim field outside [`PRIM_FIELDS`] (references,
//! payloads, inherits, specializes, variants, relocates, instancing, value clips, `primOrder`),
//! an attribute that tress reads with `timeSamples` or a blocked default, a spec that is neither
//! prim nor attribute where one is read, any spec field other than an attribute value that does
//! not decode (the stage reads fields this path does not use), and every error or panic (the
//! stage then reports it in its own words).

use std::collections::{HashMap, HashSet};
use std::io::Cursor;

use glam::DMat4;
use openusd::gf;
use openusd::sdf::{self, AbstractData, SpecType, Specifier, Value};
use openusd::usdc::CrateData;

use super::schema::Attrs;
use super::{Found, MAX_PRIMS, UsdContents, check_op_names, err, is_identifier};
use crate::HairError;
use crate::formats::curves::ReadOptions;

/// The crate reader over the caller's bytes.
type Layer<'a> = CrateData<Cursor<&'a [u8]>>;

/// Layer metadata that does not change what the stage composes.
pub(super) const ROOT_FIELDS: &[&str] = &[
    "primChildren",
    "defaultPrim",
    "documentation",
    "comment",
    "customLayerData",
    "upAxis",
    "metersPerUnit",
    "kilogramsPerUnit",
    "startTimeCode",
    "endTimeCode",
    "timeCodesPerSecond",
    "framesPerSecond",
    "framePrecision",
    "colorConfiguration",
    "colorManagementSystem",
    "owner",
];

/// Prim metadata that does not change what the stage composes.
pub(super) const PRIM_FIELDS: &[&str] = &[
    "specifier",
    "typeName",
    "primChildren",
    "propertyChildren",
    "propertyOrder",
    "active",
    "kind",
    "apiSchemas",
    "assetInfo",
    "comment",
    "customData",
    "displayName",
    "documentation",
    "hidden",
];

/// The curves and meshes of the `.usdc` file `bytes` (already checked by `usdc_check`), or
/// `None` where the stage must read it (see the module docs).
pub(super) fn read(bytes: &[u8], options: &ReadOptions) -> Option<UsdContents> {
    crate::panic_guard::quietly(|| read_layer(bytes, options)).flatten()
}

fn read_layer(bytes: &[u8], options: &ReadOptions) -> Option<UsdContents> {
    let layer: Layer<'_> = CrateData::open(Cursor::new(bytes), true).ok()?;
    let root = sdf::Path::abs_root();
    if !only_fields(&layer, &root, ROOT_FIELDS) {
        return None;
    }
    if !metadata_decodes(&layer) {
        return None;
    }
    let mut found = Found::default();
    let mut worlds = HashMap::new();
    for path in traversal(&layer)? {
        let ty = match layer.try_field(&path, "typeName").ok()? {
            Some(v) => v.into_owned().try_as_token(),
            None => None,
        };
        let ty = ty.as_ref().map(|t| t.as_str()).unwrap_or("");
        if !matches!(ty, "BasisCurves" | "NurbsCurves" | "Mesh") {
            continue;
        }
        let world = world_transform(&layer, &path, &mut worlds).ok()?;
        let prim = LayerPrim {
            layer: &layer,
            path,
        };
        found.add(&prim, ty, world, options).ok()?;
    }
    found.finish().ok()
}

/// Whether every field of every spec decodes, attribute values (`default`) aside: the stage
/// reads fields this path does not use (a prim's `propertyChildren`, for one), and a damaged one
/// must make both paths fail, not only the stage.
fn metadata_decodes(layer: &Layer<'_>) -> bool {
    layer.spec_paths().iter().all(|path| {
        let attribute = layer.spec_type(path) == Some(SpecType::Attribute);
        layer
            .list_fields(path)
            .unwrap_or_default()
            .iter()
            .all(|field| (attribute && field == "default") || layer.try_field(path, field).is_ok())
    })
}

/// Whether every field of the spec at `path` is one of `allowed`.
fn only_fields(layer: &Layer<'_>, path: &sdf::Path, allowed: &[&str]) -> bool {
    layer
        .list_fields(path)
        .unwrap_or_default()
        .iter()
        .all(|f| allowed.contains(&f.as_str()))
}

/// The prims the stage's default traversal visits, in its order; `None` where the layer needs
/// the stage. Like the stage path's hierarchy check, every child name of every prim must be a
/// prim name and the layer may hold at most [`MAX_PRIMS`] prims.
fn traversal(layer: &Layer<'_>) -> Option<Vec<sdf::Path>> {
    // (path, whether it and all its ancestors are visited)
    let mut stack = vec![(sdf::Path::abs_root(), true)];
    let mut visited = Vec::new();
    let mut prims = 0usize;
    while let Some((path, parent_visible)) = stack.pop() {
        let visible = if path.is_abs_root() {
            true
        } else {
            match layer.spec_type(&path) {
                None => false,
                Some(SpecType::Prim) => {
                    if !only_fields(layer, &path, PRIM_FIELDS) {
                        return None;
                    }
                    let def = match layer.try_field(&path, "specifier").ok()? {
                        Some(v) => match v.as_ref() {
                            Value::Specifier(s) => *s == Specifier::Def,
                            _ => return None,
                        },
                        None => false,
                    };
                    let active = match layer.try_field(&path, "active").ok()? {
                        Some(v) => match v.as_ref() {
                            Value::Bool(b) => *b,
                            _ => return None,
                        },
                        None => true,
                    };
                    parent_visible && def && active
                }
                Some(_) => return None,
            }
        };
        if visible && !path.is_abs_root() {
            visited.push(path.clone());
        }
        let names = match layer.try_field(&path, "primChildren").ok()? {
            Some(v) => match v.into_owned() {
                Value::TokenVec(names) => names,
                _ => return None,
            },
            None => Vec::new(),
        };
        let mut children = Vec::with_capacity(names.len());
        let mut seen = HashSet::with_capacity(names.len());
        for name in &names {
            if !is_identifier(name.as_str()) || !seen.insert(name.as_str()) {
                return None;
            }
            prims += 1;
            if prims > MAX_PRIMS {
                return None;
            }
            children.push((path.append_path(name.as_str()).ok()?, visible));
        }
        stack.extend(children.into_iter().rev());
    }
    Some(visited)
}

/// One prim spec of the layer.
struct LayerPrim<'a, 'b> {
    layer: &'a Layer<'b>,
    path: sdf::Path,
}

/// Why the direct path gives up (never shown: the stage then reads the file).
fn declined() -> HairError {
    err("the layer needs the stage")
}

/// The authored `default` of the attribute at `attr`, declining time samples and blocks.
fn attribute_value(layer: &Layer<'_>, attr: &sdf::Path) -> Result<Option<Value>, HairError> {
    match layer.spec_type(attr) {
        None => return Ok(None),
        Some(SpecType::Attribute) => {}
        Some(_) => return Err(declined()),
    }
    if layer.has_field(attr, "timeSamples") || layer.has_field(attr, "spline") {
        return Err(declined());
    }
    match layer.try_field(attr, "default") {
        Ok(Some(v)) => match v.into_owned() {
            Value::ValueBlock | Value::None => Err(declined()),
            v => Ok(Some(v)),
        },
        Ok(None) => Ok(None),
        Err(_) => Err(declined()),
    }
}

impl Attrs for LayerPrim<'_, '_> {
    fn prim_path(&self) -> &str {
        self.path.as_str()
    }

    fn value(&self, name: &str) -> Result<Option<Value>, HairError> {
        let attr = self.path.append_property(name).map_err(|_| declined())?;
        attribute_value(self.layer, &attr)
    }

    fn interpolation(&self, name: &str) -> Option<Value> {
        let attr = self.path.append_property(name).ok()?;
        Some(
            self.layer
                .try_field(&attr, "interpolation")
                .ok()??
                .into_owned(),
        )
    }
}

/// The prim's `xformOpOrder` as openusd's `Xformable::xform_op_order` reads it.
fn op_order(layer: &Layer<'_>, path: &sdf::Path) -> Result<Option<Vec<String>>, HairError> {
    let attr = path
        .append_property("xformOpOrder")
        .map_err(|_| declined())?;
    let v = layer
        .try_field(&attr, "default")
        .map_err(|_| declined())?
        .map(|v| v.into_owned());
    Ok(match v {
        Some(Value::TokenVec(v)) => Some(v.into_iter().map(Into::into).collect()),
        Some(Value::StringVec(v)) => Some(v),
        Some(Value::TokenListOp(op)) => Some(op.flatten().into_iter().map(Into::into).collect()),
        Some(Value::StringListOp(op)) => Some(op.flatten()),
        _ => None,
    })
}

/// Local-to-world of the prim at `path`, as the stage path's `world_transform` computes it
/// (parent × local up the namespace, stopping at `!resetXformStack!`), walked without recursion
/// so a deep hierarchy cannot exhaust the stack.
fn world_transform(
    layer: &Layer<'_>,
    path: &sdf::Path,
    cache: &mut HashMap<sdf::Path, DMat4>,
) -> Result<DMat4, HairError> {
    // The prims whose transforms are still to compute, innermost first, with their locals.
    let mut chain = Vec::new();
    let mut at = path.clone();
    let mut outer = DMat4::IDENTITY;
    loop {
        if let Some(m) = cache.get(&at) {
            outer = *m;
            break;
        }
        let (local, resets) = local_transform(layer, &at)?;
        let parent = at.parent();
        chain.push((at, local));
        match parent {
            Some(p) if !resets && p != sdf::Path::abs_root() => at = p,
            _ => break,
        }
    }
    let mut world = outer;
    for (at, local) in chain.into_iter().rev() {
        world *= local;
        if !world.is_finite() {
            return Err(declined());
        }
        cache.insert(at, world);
    }
    Ok(world)
}

/// The prim's xformOps composed (column vectors) and whether it resets the transform stack.
fn local_transform(layer: &Layer<'_>, path: &sdf::Path) -> Result<(DMat4, bool), HairError> {
    let order = op_order(layer, path)?;
    if let Some(order) = &order {
        check_op_names(order, path)?;
    }
    let order = order.unwrap_or_default();
    let mut local = gf::Matrix4d::IDENTITY;
    for (i, op) in order.iter().enumerate() {
        if op == "!resetXformStack!" {
            if i == 0 {
                continue;
            }
            return Err(declined());
        }
        local = op_matrix(layer, path, op)? * local;
    }
    // openusd's matrices are row-major for row vectors: the same numbers, column-major, are the
    // column-vector matrix.
    let resets = order.first().is_some_and(|op| op == "!resetXformStack!");
    Ok((DMat4::from_cols_array(&local.0), resets))
}

/// One xformOp's matrix, as openusd's `Xformable` builds it (row vectors).
fn op_matrix(layer: &Layer<'_>, path: &sdf::Path, op: &str) -> Result<gf::Matrix4d, HairError> {
    let (inverted, base) = match op.strip_prefix("!invert!") {
        Some(base) => (true, base),
        None => (false, op),
    };
    let attr = path.append_property(base).map_err(|_| declined())?;
    let Some(raw) = attribute_value(layer, &attr)? else {
        return Ok(gf::Matrix4d::IDENTITY);
    };
    let after_ns = base.strip_prefix("xformOp:").unwrap_or(base);
    let kind = after_ns.split(':').next().unwrap_or(after_ns);
    let scalar = |fallback: f64| scalar_of(&raw).unwrap_or(fallback);
    let m = match kind {
        "translate" => gf::Matrix4d::translation(vec3_of(&raw).unwrap_or([0.0; 3])),
        "translateX" => gf::Matrix4d::translation([scalar(0.0), 0.0, 0.0]),
        "translateY" => gf::Matrix4d::translation([0.0, scalar(0.0), 0.0]),
        "translateZ" => gf::Matrix4d::translation([0.0, 0.0, scalar(0.0)]),
        "scale" => gf::Matrix4d::scale(vec3_of(&raw).unwrap_or([1.0; 3])),
        "scaleX" => gf::Matrix4d::scale([scalar(1.0), 1.0, 1.0]),
        "scaleY" => gf::Matrix4d::scale([1.0, scalar(1.0), 1.0]),
        "scaleZ" => gf::Matrix4d::scale([1.0, 1.0, scalar(1.0)]),
        "orient" => gf::Matrix4d::from_quat(quat_of(&raw).unwrap_or([1.0, 0.0, 0.0, 0.0])),
        "rotateX" => gf::Matrix4d::rotation_x(scalar(0.0).to_radians()),
        "rotateY" => gf::Matrix4d::rotation_y(scalar(0.0).to_radians()),
        "rotateZ" => gf::Matrix4d::rotation_z(scalar(0.0).to_radians()),
        "rotateXYZ" | "rotateYXZ" | "rotateZXY" | "rotateXZY" | "rotateYZX" | "rotateZYX" => {
            let v = vec3_of(&raw).unwrap_or([0.0; 3]);
            let rx = gf::Matrix4d::rotation_x(v[0].to_radians());
            let ry = gf::Matrix4d::rotation_y(v[1].to_radians());
            let rz = gf::Matrix4d::rotation_z(v[2].to_radians());
            match kind {
                "rotateXYZ" => rx * ry * rz,
                "rotateYXZ" => ry * rx * rz,
                "rotateZXY" => rz * rx * ry,
                "rotateXZY" => rx * rz * ry,
                "rotateYZX" => ry * rz * rx,
                _ => rz * ry * rx,
            }
        }
        "transform" => match raw {
            Value::Matrix4d(m) => m,
            _ => gf::Matrix4d::IDENTITY,
        },
        _ => gf::Matrix4d::IDENTITY,
    };
    if inverted {
        m.inverse().ok_or_else(declined)
    } else {
        Ok(m)
    }
}

fn scalar_of(v: &Value) -> Option<f64> {
    match v {
        Value::Double(d) => Some(*d),
        Value::Float(f) => Some(f64::from(*f)),
        Value::Half(h) => Some(f64::from(h.to_f32())),
        Value::Int(i) => Some(f64::from(*i)),
        Value::Int64(i) => Some(*i as f64),
        _ => None,
    }
}

fn vec3_of(v: &Value) -> Option<[f64; 3]> {
    match v {
        Value::Vec3d(a) => Some([a.x, a.y, a.z]),
        Value::Vec3f(a) => Some([f64::from(a.x), f64::from(a.y), f64::from(a.z)]),
        Value::Vec3h(a) => Some([
            f64::from(a.x.to_f32()),
            f64::from(a.y.to_f32()),
            f64::from(a.z.to_f32()),
        ]),
        _ => None,
    }
}

fn quat_of(v: &Value) -> Option<[f64; 4]> {
    match v {
        Value::Quatd(q) => Some([q.w, q.x, q.y, q.z]),
        Value::Quatf(q) => Some([
            f64::from(q.w),
            f64::from(q.x),
            f64::from(q.y),
            f64::from(q.z),
        ]),
        Value::Quath(q) => Some([
            f64::from(q.w.to_f32()),
            f64::from(q.x.to_f32()),
            f64::from(q.y.to_f32()),
            f64::from(q.z.to_f32()),
        ]),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use super::*;
    use crate::formats::usd::{read_through_stage, usdc_check};
    use crate::formats::{UsdFlavor, write_usd};

    fn data_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
    }

    /// Every file under `dir` whose extension is one of `exts`.
    fn files(dir: &Path, exts: &[&str], out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                files(&path, exts, out);
            } else if path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| exts.contains(&e))
            {
                out.push(path);
            }
        }
    }

    /// `.usda` text as a crate file.
    fn crate_of(text: &str) -> Vec<u8> {
        let data = openusd::usda::parse(text).unwrap();
        let mut out = Cursor::new(Vec::new());
        openusd::usdc::CrateWriter::write(&data, &mut out).unwrap();
        out.into_inner()
    }

    /// Reads `bytes` both ways; `true` when the direct path took the file (and then its result
    /// is the stage's, asset for asset).
    fn same_both_ways(bytes: &[u8], ext: &str, what: &str) -> bool {
        let options = ReadOptions::default();
        // The crate check runs before either path (and refuses what openusd must not see).
        if bytes.starts_with(b"PXR-USDC") && usdc_check::check(bytes).is_err() {
            return false;
        }
        let stage = read_through_stage(bytes, ext, &options);
        let Some(direct) = (ext == "usdc").then(|| read(bytes, &options)).flatten() else {
            return false;
        };
        let stage =
            stage.unwrap_or_else(|e| panic!("{what}: the stage failed ({e}), the layer read"));
        assert_eq!(direct.hair, stage.hair, "{what}: curves differ");
        assert_eq!(direct.mesh, stage.mesh, "{what}: meshes differ");
        assert_eq!(direct.info, stage.info, "{what}: prims differ");
        true
    }

    #[test]
    fn every_usd_test_file_reads_the_same_without_the_stage() {
        let mut paths = Vec::new();
        files(&data_dir(), &["usdc", "usdz"], &mut paths);
        let mut direct = Vec::new();
        for path in &paths {
            let bytes = std::fs::read(path).unwrap();
            let ext = path.extension().unwrap().to_str().unwrap();
            if same_both_ways(&bytes, ext, &path.display().to_string()) {
                direct.push(path.file_name().unwrap().to_string_lossy().into_owned());
            }
        }
        assert!(direct.contains(&"groom.usdc".to_string()), "{direct:?}");
        // The text files (transforms, cubic and NURBS curves, meshes) as crate files.
        let mut texts = Vec::new();
        files(&data_dir(), &["usda"], &mut texts);
        let mut taken = 0;
        for path in &texts {
            let text = std::fs::read_to_string(path).unwrap();
            let bytes = crate_of(&text);
            taken += usize::from(same_both_ways(&bytes, "usdc", &path.display().to_string()));
        }
        // groom, cubic and nurbs; the cycle files have references.
        assert_eq!(taken, 3, "of {texts:?}");
    }

    #[test]
    fn written_grooms_read_the_same_without_the_stage() {
        use glam::{Vec2, Vec3};
        let positions = (0..40)
            .map(|i| Vec3::new(i as f32, (i % 4) as f32, 0.5))
            .collect();
        let a = crate::HairAsset::from_counts(positions, &[4; 10])
            .and_then(|a| a.with_thickness((0..40).map(|i| 0.01 + i as f32 * 1e-3).collect()))
            .and_then(|a| a.with_color(vec![Vec3::new(0.3, 0.2, 0.1); 40]))
            .and_then(|a| a.with_transparency(vec![0.25; 40]))
            .and_then(|a| a.with_strand_uv(vec![Vec2::new(0.5, 0.25); 10]))
            .unwrap();
        let bytes = write_usd(&a, UsdFlavor::Binary).unwrap();
        assert!(same_both_ways(&bytes, "usdc", "written groom"));
    }

    #[test]
    fn transforms_and_hidden_prims_read_the_same_without_the_stage() {
        let curves = |name: &str, spec: &str| {
            format!(
                "{spec} BasisCurves \"{name}\" {{\n int[] curveVertexCounts = [2]\n point3f[] points = [(0,0,0), (0,1,2)]\n uniform token type = \"linear\"\n float[] widths = [0.1, 0.2] (interpolation = \"vertex\")\n}}\n"
            )
        };
        let text = format!(
            "#usda 1.0\n\
             def Xform \"A\" {{\n double3 xformOp:translate = (1, 2, 3)\n float3 xformOp:rotateXYZ = (10, 20, 30)\n quatf xformOp:orient = (0.9, 0.1, 0.3, 0.2)\n uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:rotateXYZ\", \"!invert!xformOp:orient\"]\n\
             def Xform \"B\" {{\n matrix4d xformOp:transform = ((2,0,0,0),(0,1,0,0),(0,0,1,0),(5,0,0,1))\n double xformOp:rotateZ:tilt = 15\n uniform token[] xformOpOrder = [\"xformOp:transform\", \"xformOp:rotateZ:tilt\"]\n{}{}\n }}\n\
             def Xform \"R\" {{\n float3 xformOp:scale = (2, 3, 4)\n uniform token[] xformOpOrder = [\"!resetXformStack!\", \"xformOp:scale\"]\n{}\n }}\n\
             }}\n\
             def Xform \"Off\" (\n active = false\n) {{\n{}}}\n\
             over \"Over\" {{\n{}}}\n\
             class \"Class\" {{\n{}}}\n",
            curves("C1", "def"),
            curves("C2", "def"),
            curves("C3", "def"),
            curves("C4", "def"),
            curves("C5", "def"),
            curves("C6", "def"),
        );
        let bytes = crate_of(&text);
        assert!(same_both_ways(&bytes, "usdc", &text));
        let c = read(&bytes, &ReadOptions::default()).unwrap();
        assert_eq!(c.info.prims, ["/A/B/C1", "/A/B/C2", "/A/R/C3"]);
    }

    /// Every one-byte change of `groom.usdc` (four values per byte) that passes the crate check
    /// and that the direct path reads, the stage reads to the same assets: a damaged field the
    /// stage trips on must not be one the direct path skips.
    #[test]
    fn damaged_files_read_the_same_both_ways() {
        let orig = std::fs::read(data_dir().join("groom.usdc")).unwrap();
        let options = ReadOptions::default();
        let mut taken = 0;
        for at in 0..orig.len() {
            for byte in [0u8, 0xff, orig[at] ^ 1, orig[at] ^ 0x80] {
                let mut bytes = orig.clone();
                bytes[at] = byte;
                if usdc_check::check(&bytes).is_err() || read(&bytes, &options).is_none() {
                    continue;
                }
                taken += 1;
                assert!(same_both_ways(
                    &bytes,
                    "usdc",
                    &format!("byte {at} = {byte}")
                ));
            }
        }
        assert!(taken > 1000, "{taken}");
    }

    #[test]
    fn composition_arcs_and_time_samples_take_the_stage() {
        let curves = "def BasisCurves \"C\" {\n int[] curveVertexCounts = [2]\n point3f[] points = [(0,0,0), (0,1,0)]\n uniform token type = \"linear\"\n}\n";
        let cases = [
            format!("#usda 1.0\n(\n subLayers = [@other.usda@]\n)\n{curves}"),
            format!("#usda 1.0\n{curves}def Xform \"R\" (\n references = </C>\n)\n{{\n}}\n"),
            format!("#usda 1.0\n{curves}def Xform \"P\" (\n payload = @other.usda@</X>\n)\n{{\n}}\n"),
            format!("#usda 1.0\n{curves}def Xform \"I\" (\n inherits = </C>\n)\n{{\n}}\n"),
            format!("#usda 1.0\n{curves}def Xform \"S\" (\n specializes = </C>\n)\n{{\n}}\n"),
            format!(
                "#usda 1.0\ndef Xform \"V\" (\n variants = {{ string look = \"a\" }}\n prepend variantSets = \"look\"\n)\n{{\n variantSet \"look\" = {{\n \"a\" {{\n{curves} }}\n }}\n}}\n"
            ),
            "#usda 1.0\ndef BasisCurves \"T\" {\n int[] curveVertexCounts = [2]\n point3f[] points.timeSamples = { 1: [(0,0,0), (0,1,0)] }\n uniform token type = \"linear\"\n}\n".to_string(),
        ];
        let options = ReadOptions::default();
        for text in &cases {
            let bytes = crate_of(text);
            assert!(
                read(&bytes, &options).is_none(),
                "the layer path took\n{text}"
            );
            assert!(!same_both_ways(&bytes, "usdc", text));
        }
        // Without the arc, the same curves take the direct path.
        let plain = crate_of(&format!("#usda 1.0\n{curves}"));
        assert!(same_both_ways(&plain, "usdc", "plain curves"));
    }
}
