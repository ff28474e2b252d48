//! An animated cache (`write_animated`): every frame of `P` reads back as written, a frame past
//! the last reads the last, `P`'s time sampling gives the seconds between frames, and the other
//! properties keep their one sample.

use tress_alembic::write::{CurvesOut, TimeSampling, write_animated};
use tress_alembic::{read, read_frame};

fn frame(k: usize) -> Vec<[f32; 3]> {
    (0..7)
        .map(|i| [i as f32, k as f32 * 0.5, (i * k) as f32 * 0.25])
        .collect()
}

fn cache() -> Vec<u8> {
    let c = CurvesOut {
        name: "hair".into(),
        positions: frame(0),
        vertex_counts: vec![3, 4],
        widths: Some((tress_alembic::Scope::Vertex, vec![0.1; 7])),
        frames: (1..5).map(frame).collect(),
        ..CurvesOut::default()
    };
    write_animated(
        &[c],
        TimeSampling {
            seconds_per_frame: 1.0 / 24.0,
            start: 1.0 / 24.0,
        },
    )
}

#[test]
fn every_frame_reads_back_as_written() {
    let bytes = cache();
    for k in 0..5 {
        let c = read_frame(&bytes, k as u32).unwrap();
        assert_eq!(c.curves.len(), 1);
        assert_eq!(c.curves[0].positions, frame(k), "frame {k}");
        assert_eq!(c.curves[0].position_samples, 5);
        assert_eq!(c.curves[0].seconds_per_position_sample, Some(1.0 / 24.0));
        assert_eq!(c.curves[0].vertex_counts, vec![3, 4]);
        assert_eq!(c.curves[0].widths.as_ref().unwrap().values, vec![0.1; 7]);
    }
    assert_eq!(
        read_frame(&bytes, 99).unwrap().curves[0].positions,
        frame(4)
    );
    assert_eq!(read(&bytes).unwrap().curves[0].positions, frame(0));
}

#[test]
fn a_static_file_has_one_sample_at_every_frame() {
    let c = CurvesOut {
        name: "hair".into(),
        positions: frame(3),
        vertex_counts: vec![7],
        ..CurvesOut::default()
    };
    let bytes = tress_alembic::write::write(&[c]);
    let r = read_frame(&bytes, 3).unwrap();
    assert_eq!(r.curves[0].positions, frame(3));
    assert_eq!(r.curves[0].position_samples, 1);
    assert_eq!(r.curves[0].seconds_per_position_sample, None);
}
