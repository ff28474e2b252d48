//! A minimal Ogawa Alembic writer of curves (cargo feature `write`): what the tests, the
//! benchmark and the fuzz seeds need to make files of any size without Python. It writes the
//! layout [`crate::read`] documents: one Xform per curves object when it has a matrix (as one
//! matrix operation), `P`, `nVertices`, `curveBasisAndType`, `width` and the Unreal groom
//! attributes, one sample each. It is not a general Alembic writer: no time sampling beyond
//! frame 0, no bounds, zero digests.

use crate::{Basis, CurveType, Scope, Wrap};

const DATA_BIT: u64 = 1 << 63;

/// One curves object to write.
#[derive(Clone, Debug, Default)]
pub struct CurvesOut {
    /// Object name (below the top object, or below its Xform).
    pub name: String,
    /// A parent Xform's matrix (column-major, column vectors), written as one matrix operation.
    pub xform: Option<[f64; 16]>,
    /// Vertices.
    pub positions: Vec<[f32; 3]>,
    /// Vertex count per curve.
    pub vertex_counts: Vec<i32>,
    /// Curve type, wrap and basis.
    pub kind: Option<(CurveType, Wrap, Basis)>,
    /// Widths and their scope.
    pub widths: Option<(Scope, Vec<f32>)>,
    /// `groom_color` and its scope.
    pub colors: Option<(Scope, Vec<[f32; 3]>)>,
    /// `groom_root_uv` (per curve).
    pub root_uv: Option<Vec<[f32; 2]>>,
    /// `groom_guide` (per curve).
    pub guide: Option<Vec<i32>>,
}

struct Out {
    bytes: Vec<u8>,
}

impl Out {
    fn data(&mut self, payload: &[u8]) -> u64 {
        if payload.is_empty() {
            return DATA_BIT;
        }
        let at = self.bytes.len() as u64;
        self.bytes
            .extend_from_slice(&(payload.len() as u64).to_le_bytes());
        self.bytes.extend_from_slice(payload);
        at | DATA_BIT
    }

    fn group(&mut self, children: &[u64]) -> u64 {
        let at = self.bytes.len() as u64;
        self.bytes
            .extend_from_slice(&(children.len() as u64).to_le_bytes());
        for c in children {
            self.bytes.extend_from_slice(&c.to_le_bytes());
        }
        at
    }

    /// A sample block: 16 digest bytes, then the values.
    fn sample(&mut self, values: &[u8]) -> u64 {
        let mut v = vec![0u8; 16];
        v.extend_from_slice(values);
        self.data(&v)
    }
}

/// A property being built: its group and its header bytes.
struct Prop {
    group: u64,
    header: Vec<u8>,
}

fn header(kind: u32, pod: u32, extent: u32, name: &str, metadata: &str) -> Vec<u8> {
    // sizes as u32 (hint 2), constant, homogeneous, metadata inline (index 0xff)
    let mut info = kind | (2 << 2) | (0xff << 20);
    if kind != 0 {
        info |= (pod << 4) | 0x400 | 0x800 | (extent << 12);
    }
    let mut h = info.to_le_bytes().to_vec();
    if kind != 0 {
        h.extend_from_slice(&1u32.to_le_bytes());
    }
    h.extend_from_slice(&(name.len() as u32).to_le_bytes());
    h.extend_from_slice(name.as_bytes());
    h.extend_from_slice(&(metadata.len() as u32).to_le_bytes());
    h.extend_from_slice(metadata.as_bytes());
    h
}

fn words<T: Copy, const N: usize>(values: &[T], to: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    values.iter().flat_map(|&v| to(v)).collect()
}

fn array(out: &mut Out, name: &str, pod: u32, extent: u32, values: &[u8], meta: &str) -> Prop {
    let d = out.sample(values);
    let group = out.group(&[d, DATA_BIT]);
    Prop {
        group,
        header: header(2, pod, extent, name, meta),
    }
}

fn scalar(out: &mut Out, name: &str, pod: u32, extent: u32, values: &[u8]) -> Prop {
    let d = out.sample(values);
    let group = out.group(&[d]);
    Prop {
        group,
        header: header(1, pod, extent, name, ""),
    }
}

fn compound(out: &mut Out, name: &str, props: Vec<Prop>, meta: &str) -> Prop {
    let group = compound_group(out, props);
    Prop {
        group,
        header: header(0, 0, 0, name, meta),
    }
}

fn compound_group(out: &mut Out, props: Vec<Prop>) -> u64 {
    let mut children: Vec<u64> = props.iter().map(|p| p.group).collect();
    let headers: Vec<u8> = props.into_iter().flat_map(|p| p.header).collect();
    children.push(out.data(&headers));
    out.group(&children)
}

fn scope_name(scope: Scope) -> &'static str {
    match scope {
        Scope::Constant => "con",
        Scope::Uniform => "uni",
        Scope::Varying => "var",
        Scope::Vertex => "vtx",
        Scope::FaceVarying => "fvr",
        Scope::Unknown => "",
    }
}

fn param_meta(scope: Scope, extent: u32) -> String {
    format!(
        "geoScope={};isGeomParam=true;podExtent={extent}",
        scope_name(scope)
    )
}

fn curves_object(out: &mut Out, c: &CurvesOut) -> u64 {
    let f32s = |v: &[f32]| words(v, f32::to_le_bytes);
    let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
    let mut geom = vec![
        array(
            out,
            "P",
            10,
            3,
            &f32s(&flat(&c.positions)),
            "geoScope=vtx;interpretation=point",
        ),
        array(
            out,
            "nVertices",
            6,
            1,
            &words(&c.vertex_counts, i32::to_le_bytes),
            "",
        ),
    ];
    let (kind, wrap, basis) = c
        .kind
        .unwrap_or((CurveType::Linear, Wrap::NonPeriodic, Basis::None));
    let kind = match kind {
        CurveType::Cubic => 0,
        CurveType::Linear => 1,
        CurveType::VariableOrder => 2,
    };
    let wrap = u8::from(wrap == Wrap::Periodic);
    let basis = match basis {
        Basis::None => 0,
        Basis::Bezier => 1,
        Basis::Bspline => 2,
        Basis::CatmullRom => 3,
        Basis::Hermite => 4,
        Basis::Power => 5,
    };
    geom.push(scalar(
        out,
        "curveBasisAndType",
        1,
        4,
        &[kind, wrap, basis, basis],
    ));
    if let Some((scope, w)) = &c.widths {
        geom.push(array(out, "width", 10, 1, &f32s(w), &param_meta(*scope, 1)));
    }
    let mut arb = Vec::new();
    if let Some((scope, colors)) = &c.colors {
        arb.push(array(
            out,
            "groom_color",
            10,
            3,
            &f32s(&flat(colors)),
            &param_meta(*scope, 3),
        ));
    }
    if let Some(uv) = &c.root_uv {
        let v: Vec<f32> = uv.iter().flatten().copied().collect();
        arb.push(array(
            out,
            "groom_root_uv",
            10,
            2,
            &f32s(&v),
            &param_meta(Scope::Uniform, 2),
        ));
    }
    if let Some(g) = &c.guide {
        let meta = param_meta(Scope::Uniform, 1);
        arb.push(array(
            out,
            "groom_guide",
            6,
            1,
            &words(g, i32::to_le_bytes),
            &meta,
        ));
    }
    if !arb.is_empty() {
        geom.push(compound(out, ".arbGeomParams", arb, ""));
    }
    let geom = compound(
        out,
        ".geom",
        geom,
        "schema=AbcGeom_Curve_v2;schemaObjTitle=AbcGeom_Curve_v2:.geom",
    );
    let props = compound_group(out, vec![geom]);
    let headers = out.data(&[0u8; 32]);
    out.group(&[props, headers])
}

fn object_headers(children: &[(&str, &str)]) -> Vec<u8> {
    let mut h = Vec::new();
    for (name, meta) in children {
        h.extend_from_slice(&(name.len() as u32).to_le_bytes());
        h.extend_from_slice(name.as_bytes());
        h.push(0xff);
        h.extend_from_slice(&(meta.len() as u32).to_le_bytes());
        h.extend_from_slice(meta.as_bytes());
    }
    h.extend_from_slice(&[0u8; 32]);
    h
}

const CURVE_META: &str = "schema=AbcGeom_Curve_v2;schemaObjTitle=AbcGeom_Curve_v2:.geom";
const XFORM_META: &str = "schema=AbcGeom_Xform_v3;schemaObjTitle=AbcGeom_Xform_v3:.xform";

/// An Ogawa Alembic file holding `curves` below the top object.
pub fn write(curves: &[CurvesOut]) -> Vec<u8> {
    let mut out = Out {
        bytes: vec![0u8; 16],
    };
    let mut top_children = Vec::new();
    let mut names = Vec::new();
    for c in curves {
        let obj = curves_object(&mut out, c);
        match c.xform {
            Some(m) => {
                let vals: Vec<u8> = m.iter().flat_map(|v| v.to_le_bytes()).collect();
                let x = vec![
                    scalar(&mut out, ".inherits", 0, 1, &[1]),
                    scalar(&mut out, ".ops", 1, 1, &[0x30]),
                    scalar(&mut out, ".vals", 11, 16, &vals),
                ];
                let xform = compound(&mut out, ".xform", x, XFORM_META);
                let props = compound_group(&mut out, vec![xform]);
                let name = c.name.clone();
                let headers = out.data(&object_headers(&[(&name, CURVE_META)]));
                top_children.push(out.group(&[props, obj, headers]));
                names.push((format!("{}_xform", c.name), XFORM_META));
            }
            None => {
                top_children.push(obj);
                names.push((c.name.clone(), CURVE_META));
            }
        }
    }
    let top_props = out.group(&[]);
    let refs: Vec<(&str, &str)> = names.iter().map(|(n, m)| (n.as_str(), *m)).collect();
    let headers = out.data(&object_headers(&refs));
    let mut top = vec![top_props];
    top.extend_from_slice(&top_children);
    top.push(headers);
    let top = out.group(&top);
    let version = out.data(&0i32.to_le_bytes());
    let library = out.data(&10709i32.to_le_bytes());
    let meta = out.data(b"_ai_Application=tress");
    let mut ts = 1u32.to_le_bytes().to_vec();
    ts.extend_from_slice(&1f64.to_le_bytes());
    ts.extend_from_slice(&1u32.to_le_bytes());
    ts.extend_from_slice(&0f64.to_le_bytes());
    let times = out.data(&ts);
    let indexed = DATA_BIT;
    let root = out.group(&[version, library, top, meta, times, indexed]);
    out.bytes[..8].copy_from_slice(b"Ogawa\xff\x00\x01");
    out.bytes[8..16].copy_from_slice(&root.to_le_bytes());
    out.bytes
}
