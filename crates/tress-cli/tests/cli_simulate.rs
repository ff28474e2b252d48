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

#[test]
fn a_simulation_cache_is_written_and_plays_back_a_frame_at_a_time() {
    if skip_gpu() {
        return;
    }
    let cache = tmp("sim-cache.abc");
    let run = tress(&[
        "simulate",
        &scene(),
        "--frames",
        "4",
        "--set",
        "hair.0.strand_ratio=0.02",
        "--json",
        "-o",
        s(&cache),
    ]);
    assert_gpu_success(&run);
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(v["frames"], 4);
    // 24 fps against the 60 Hz rate: 0, 2, 5 and 7 steps by frames 0–3.
    assert_eq!(v["steps"], 7);
    let strands = v["strands"].as_u64().unwrap() as usize;
    assert!(v["guides"].as_u64().unwrap() > 0);
    assert_eq!(
        v["cache_bytes"].as_u64().unwrap(),
        std::fs::metadata(&cache).unwrap().len()
    );
    // Each simulation pass's GPU time, where the device has timestamps (lavapipe has).
    if let Some(total) = v["simulate_gpu_ms_mean"].as_f64() {
        let passes = v["passes"].as_array().unwrap();
        let names: Vec<&str> = passes.iter().map(|p| p["name"].as_str().unwrap()).collect();
        assert_eq!(
            names,
            ["sim/integrate", "sim/grid", "sim/constraints", "sim/output"]
        );
        let sum: f64 = passes.iter().map(|p| p["gpu_ms"].as_f64().unwrap()).sum();
        assert!(
            (sum - total).abs() < 1e-6 && total > 0.0,
            "{sum} vs {total}"
        );
    } else {
        assert_eq!(v["passes"].as_array().unwrap().len(), 0);
    }
    // Read back a frame at a time: the strands all there, the hair moving.
    let at = |k: u32| {
        let options = tress_hair::formats::ReadOptions {
            frame: k,
            ..Default::default()
        };
        tress_hair::formats::load_path(&cache, &options)
            .unwrap()
            .asset
    };
    let (first, last) = (at(0), at(3));
    assert_eq!(first.strand_count(), strands);
    let moved = first
        .positions()
        .iter()
        .zip(last.positions())
        .map(|(a, b)| a.distance(*b))
        .fold(0.0f32, f32::max);
    assert!(moved > 0.1, "the hair moved {moved} over the cache");
    // `tress render CACHE --frame K` draws frame K.
    let render = |k: &str, name: &str| {
        let out = tmp(name);
        let run = tress(&[
            "render",
            s(&cache),
            "--frame",
            k,
            "--width",
            "160",
            "--height",
            "90",
            "-o",
            s(&out),
        ]);
        assert_gpu_success(&run);
        image::open(&out).unwrap().to_rgb8()
    };
    let (a, b) = (render("0", "cache-0.png"), render("3", "cache-3.png"));
    let changed = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 16))
        .count();
    assert!(
        changed > 20,
        "only {changed} pixels differ between frames 0 and 3"
    );
}

#[test]
fn bad_simulate_arguments_are_one_line_errors() {
    for (args, needle) in [
        (vec!["-o", "x.hair"], ".abc, .usda, .usdc or .usd"),
        (vec!["-o", "x.abc", "--frames", "0"], "--frames"),
        (vec!["-o", "x.abc", "--fps", "0"], "--fps"),
        (vec!["-o", "x.abc", "--motion", "spin"], "--motion"),
        (
            vec!["-o", "x.abc", "--set", "simulation.damping=-1"],
            "simulation.damping",
        ),
    ] {
        let mut all = vec!["simulate"];
        all.extend(&args);
        let out = tmp(args[1]);
        let out_s = out.to_str().unwrap().to_string();
        let all: Vec<&str> = all
            .into_iter()
            .map(|a| if a == args[1] { out_s.as_str() } else { a })
            .collect();
        let run = tress(&all);
        assert_eq!(run.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}
