//! `tress render --frames N --animate simulate` end to end: the simulated hair moves between
//! frames, the steps follow the fixed rate, and bad settings or a technique that cannot draw
//! simulated hair are one-line errors.

mod common;
use common::{assert_gpu_success, skip_gpu, tmp, tress};

fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

fn scene() -> String {
    format!("{}/../../scenes/simulate.toml", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn a_simulated_sequence_moves_the_hair_at_the_fixed_rate() {
    if skip_gpu() {
        return;
    }
    let out = tmp("sim.png");
    let run = tress(&[
        "render",
        &scene(),
        "--frames",
        "4",
        "--width",
        "160",
        "--height",
        "90",
        "--set",
        "hair.0.strand_ratio=0.02",
        "--json",
        "-o",
        s(&out),
    ]);
    assert_gpu_success(&run);
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let sim = v["simulation"]
        .as_array()
        .expect("a simulation report per frame");
    assert_eq!(sim.len(), 4);
    // Frames are 1/24 s apart and the simulation steps at 60 Hz: 0, 2, 5 and 7 steps in all.
    let steps: Vec<u64> = sim.iter().map(|f| f["steps"].as_u64().unwrap()).collect();
    let total: Vec<u64> = steps
        .iter()
        .scan(0, |acc, s| {
            *acc += s;
            Some(*acc)
        })
        .collect();
    assert_eq!(total, [0, 2, 5, 7]);
    let guides = sim[0]["guides"].as_u64().unwrap();
    let strands = sim[0]["strands"].as_u64().unwrap();
    assert!(
        guides > 0 && strands > 10 * guides,
        "{guides} guides of {strands} strands"
    );
    // The hair moved: the last frame differs from the first, and more than the head alone does.
    let frame = |i: u32| {
        image::open(out.with_file_name(format!("sim-{i:04}.png")))
            .unwrap()
            .to_rgb8()
    };
    let (a, b) = (frame(0), frame(3));
    let changed = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 16))
        .count();
    assert!(
        changed > 200,
        "only {changed} pixels changed between frames 0 and 3"
    );
}

#[test]
fn bad_simulation_settings_and_techniques_are_one_line_errors() {
    let out = tmp("bad.png");
    let run = tress(&[
        "render",
        &scene(),
        "--frames",
        "2",
        "--set",
        "simulation.local_stiffness=1.5",
        "-o",
        s(&out),
    ]);
    assert_eq!(run.status.code(), Some(2));
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("simulation.local_stiffness"), "{err}");
    let run = tress(&[
        "render",
        &scene(),
        "--frames",
        "2",
        "--set",
        "simulation.wind.direction=[nan, 0.0, 0.0]",
        "-o",
        s(&out),
    ]);
    assert_eq!(run.status.code(), Some(2));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("simulation.wind.direction") || err.contains("nan"),
        "{err}"
    );
    let run = tress(&[
        "render",
        &scene(),
        "--frames",
        "2",
        "--set",
        "simulation.rate_hz=0",
        "-o",
        s(&out),
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("simulation.rate_hz"));
    let run = tress(&[
        "render",
        &scene(),
        "--frames",
        "2",
        "--set",
        "simulation.stiffnes=0.5",
        "-o",
        s(&out),
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("stiffnes"));
    let run = tress(&[
        "render",
        &scene(),
        "--frames",
        "2",
        "--technique",
        "patches",
        "--animate",
        "simulate",
        "-o",
        s(&out),
    ]);
    assert_eq!(run.status.code(), Some(2));
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("strands"), "{err}");
}
