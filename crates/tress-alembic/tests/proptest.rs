//! Property tests: files of the minimal writer read back to what was written, whatever the
//! counts; and no damaged file (truncated, bytes changed, counts made huge) makes the reader
//! panic or allocate beyond the file.

use proptest::prelude::*;
use tress_alembic::write::{CurvesOut, write};
use tress_alembic::{Basis, CurveType, Scope, Wrap, read};

fn curves(counts: &[i32], seed: f32, guide: bool) -> CurvesOut {
    let n: i32 = counts.iter().sum();
    CurvesOut {
        name: format!("c{}", counts.len()),
        xform: (seed > 0.0).then_some([
            1.0,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            f64::from(seed),
            0.0,
            1.0,
        ]),
        positions: (0..n)
            .map(|i| [i as f32, seed, -(i as f32) * 0.5])
            .collect(),
        vertex_counts: counts.to_vec(),
        kind: Some((CurveType::Cubic, Wrap::NonPeriodic, Basis::Bspline)),
        widths: Some((Scope::Vertex, (0..n).map(|i| i as f32 * 0.01).collect())),
        colors: Some((Scope::Uniform, vec![[0.5, 0.25, 0.125]; counts.len()])),
        root_uv: Some(vec![[0.5, 0.5]; counts.len()]),
        guide: guide.then(|| (0..counts.len() as i32).map(|i| i % 2).collect()),
        frames: Vec::new(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn written_curves_read_back(
        objects in prop::collection::vec((prop::collection::vec(1i32..10, 1..6), -3.0f32..3.0, any::<bool>()), 1..4),
    ) {
        let written: Vec<CurvesOut> = objects.iter().map(|(c, s, g)| curves(c, *s, *g)).collect();
        let back = read(&write(&written)).unwrap();
        prop_assert_eq!(back.curves.len(), written.len());
        for (r, w) in back.curves.iter().zip(&written) {
            prop_assert_eq!(&r.positions, &w.positions);
            prop_assert_eq!(r.vertex_counts.iter().map(|&c| c as i32).collect::<Vec<_>>(), w.vertex_counts.clone());
            prop_assert_eq!((r.kind, r.basis), (CurveType::Cubic, Basis::Bspline));
            prop_assert_eq!(&r.widths.as_ref().unwrap().values, &w.widths.as_ref().unwrap().1);
            prop_assert_eq!(r.colors.as_ref().unwrap().scope, Scope::Uniform);
            prop_assert_eq!(r.guide.as_ref().map(|g| g.values.len()), w.guide.as_ref().map(Vec::len));
            let dy = w.xform.map_or(0.0, |m| m[13]);
            prop_assert_eq!(r.world[13], dy);
        }
    }

    #[test]
    fn damaged_files_never_panic(
        counts in prop::collection::vec(1i32..6, 1..4),
        cut in 0usize..4000,
        edits in prop::collection::vec((0usize..4000, any::<u8>()), 0..6),
        big in prop::option::of((0usize..4000, any::<u64>())),
    ) {
        let mut bytes = write(&[curves(&counts, 1.0, true)]);
        for (at, b) in edits {
            if at < bytes.len() { bytes[at] = b; }
        }
        if let Some((at, v)) = big
            && at + 8 <= bytes.len()
        {
            bytes[at..at + 8].copy_from_slice(&v.to_le_bytes());
        }
        bytes.truncate(cut.max(16));
        let _ = read(&bytes);
    }
}

#[test]
fn a_cycle_in_the_offsets_is_an_error() {
    // The top object's group lists itself as its own child object.
    let mut bytes = write(&[curves(&[2], 0.0, false)]);
    let root = u64::from_le_bytes(bytes[8..16].try_into().unwrap()) as usize;
    let top = u64::from_le_bytes(bytes[root + 8 + 16..root + 8 + 24].try_into().unwrap()) as usize;
    // top group children: [props, curves object, headers]; point the curves object at `top`.
    bytes[top + 8 + 8..top + 8 + 16].copy_from_slice(&(top as u64).to_le_bytes());
    let e = read(&bytes).unwrap_err().to_string();
    assert!(e.contains("reached twice"), "{e}");
}
