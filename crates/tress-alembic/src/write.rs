//! A minimal Ogawa Alembic writer of curves (cargo feature `write`): what the tests, the
//! benchmark and the fuzz seeds need to make files of any size without Python, and the
//! simulation caches `tress simulate` writes. It writes the layout [`crate::read`] documents:
//! one Xform per curves object when it has a matrix (as one matrix operation), `P`,
//! `nVertices`, `curveBasisAndType`, `width` and the Unreal groom attributes, one sample each,
//! except `P` of a curves object with [`CurvesOut::frames`]: one sample a frame on a uniform
//! time sampling ([`write_animated`]). It is not a general Alembic writer: no bounds, and the
//! 16-byte sample digests are a 128-bit FNV-1a pair, not the Alembic library's MurmurHash3
//! (readers use a digest as a sample's cache key, so it need only tell samples apart).

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
    /// `P` at the frames after the first (`positions`), each as many vertices: an animated
    /// cache (written with [`write_animated`]'s time sampling).
    pub frames: Vec<Vec<[f32; 3]>>,
}

/// A uniform time sampling: frame `k` at `start + k · seconds_per_frame` seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeSampling {
    /// Seconds between frames (1 / fps).
    pub seconds_per_frame: f64,
    /// The first frame's time, seconds.
    pub start: f64,
}

/// Two 64-bit FNV-1a hashes of `bytes` from different offsets: a 16-byte sample digest.
fn digest(bytes: &[u8]) -> [u8; 16] {
    let hash = |seed: u64| {
        bytes.iter().fold(seed, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        })
    };
    let mut d = [0u8; 16];
    d[..8].copy_from_slice(&hash(0xcbf2_9ce4_8422_2325).to_le_bytes());
    d[8..].copy_from_slice(&hash(0x6c62_272e_07bb_0142 ^ bytes.len() as u64).to_le_bytes());
    d
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
        let mut v = digest(values).to_vec();
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

/// A scalar (`kind` 1) or array (2) property with one sample a frame on time sampling 1 (all
/// stored: first changed 1, last changed `samples − 1`).
fn animated(
    out: &mut Out,
    (kind, name, pod, extent): (u32, &str, u32, u32),
    samples: &[Vec<u8>],
    meta: &str,
) -> Prop {
    let mut children = Vec::with_capacity(2 * samples.len());
    for s in samples {
        children.push(out.sample(s));
        if kind == 2 {
            children.push(DATA_BIT);
        }
    }
    let group = out.group(&children);
    let n = samples.len() as u32;
    // sizes as u32, POD, has a time sampling index (8), first/last changed (9), homogeneous
    // (10), extent, metadata inline
    let info = kind | (2 << 2) | (pod << 4) | 0x100 | 0x200 | 0x400 | (extent << 12) | (0xff << 20);
    let mut h = info.to_le_bytes().to_vec();
    for v in [n, 1, n - 1, 1] {
        h.extend_from_slice(&v.to_le_bytes());
    }
    h.extend_from_slice(&(name.len() as u32).to_le_bytes());
    h.extend_from_slice(name.as_bytes());
    h.extend_from_slice(&(meta.len() as u32).to_le_bytes());
    h.extend_from_slice(meta.as_bytes());
    Prop { group, header: h }
}

fn scalar(out: &mut Out, name: &str, pod: u32, extent: u32, values: &[u8]) -> Prop {
    scalar_meta(out, name, pod, extent, values, "")
}

fn scalar_meta(
    out: &mut Out,
    name: &str,
    pod: u32,
    extent: u32,
    values: &[u8],
    meta: &str,
) -> Prop {
    let d = out.sample(values);
    let group = out.group(&[d]);
    Prop {
        group,
        header: header(1, pod, extent, name, meta),
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
    const P_META: &str = "geoScope=vtx;interpretation=point";
    const BOX_META: &str = "interpretation=box";
    // `.selfBnds` (the Alembic library requires it): the box of each frame's points.
    let bounds = |f: &[[f32; 3]]| {
        let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
        for p in f {
            for k in 0..3 {
                lo[k] = lo[k].min(f64::from(p[k]));
                hi[k] = hi[k].max(f64::from(p[k]));
            }
        }
        if f.is_empty() {
            (lo, hi) = ([0.0; 3], [0.0; 3]);
        }
        lo.iter()
            .chain(&hi)
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<u8>>()
    };
    let (p, bnds) = if c.frames.is_empty() {
        (
            array(out, "P", 10, 3, &f32s(&flat(&c.positions)), P_META),
            scalar_meta(out, ".selfBnds", 11, 6, &bounds(&c.positions), BOX_META),
        )
    } else {
        let all: Vec<&Vec<[f32; 3]>> = std::iter::once(&c.positions).chain(&c.frames).collect();
        let samples: Vec<Vec<u8>> = all.iter().map(|f| f32s(&flat(f))).collect();
        let boxes: Vec<Vec<u8>> = all.iter().map(|f| bounds(f)).collect();
        (
            animated(out, (2, "P", 10, 3), &samples, P_META),
            animated(out, (1, ".selfBnds", 11, 6), &boxes, BOX_META),
        )
    };
    let mut geom = vec![
        bnds,
        p,
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
    write_animated(
        curves,
        TimeSampling {
            seconds_per_frame: 1.0,
            start: 0.0,
        },
    )
}

/// [`write`](fn@write), with the curves objects' [`CurvesOut::frames`] as samples of `P` on the
/// uniform time sampling `time` (the archive's time sampling 1).
pub fn write_animated(curves: &[CurvesOut], time: TimeSampling) -> Vec<u8> {
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
    // Time samplings: 0 the identity; 1 uniform, used by animated `P` (max samples, seconds
    // per cycle, one time a cycle, the start).
    let mut ts = 1u32.to_le_bytes().to_vec();
    ts.extend_from_slice(&1f64.to_le_bytes());
    ts.extend_from_slice(&1u32.to_le_bytes());
    ts.extend_from_slice(&0f64.to_le_bytes());
    let frames = curves.iter().map(|c| c.frames.len() + 1).max().unwrap_or(1);
    if curves.iter().any(|c| !c.frames.is_empty()) {
        ts.extend_from_slice(&(frames as u32).to_le_bytes());
        ts.extend_from_slice(&time.seconds_per_frame.to_le_bytes());
        ts.extend_from_slice(&1u32.to_le_bytes());
        ts.extend_from_slice(&time.start.to_le_bytes());
    }
    let times = out.data(&ts);
    let indexed = DATA_BIT;
    let root = out.group(&[version, library, top, meta, times, indexed]);
    out.bytes[..8].copy_from_slice(b"Ogawa\xff\x00\x01");
    out.bytes[8..16].copy_from_slice(&root.to_le_bytes());
    out.bytes
}
