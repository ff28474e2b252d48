//! The CPU twin against physics with known answers, and the properties the issue names: a
//! pendulum's period, a hanging chain's rest shape and first mode, damping at any rate, a groom
//! at rest staying put at every iteration count, inextensibility and pinned roots through a fast
//! shake, no vertex inside the head through a fast turn, display-rate independence, teleports,
//! determinism.

use std::f32::consts::{PI, TAU};

use glam::{Quat, Vec3};
use tress_hair::HairAsset;
use tress_hair::generate::{Style, generate, head_for};
use tress_sim::{GuideChoice, MotionSpec, Preset, Rigid, SimSettings, Simulation};

const G: f32 = 981.0;

/// Settings with nothing but gravity (and the given rate, substeps, iterations).
fn bare(rate: f32, substeps: u32, iterations: u32) -> SimSettings {
    SimSettings {
        rate_hz: rate,
        substeps,
        iterations,
        damping: 0.0,
        local_stiffness: 0.0,
        global_stiffness: 0.0,
        hair_friction: 0.0,
        hair_volume: 0.0,
        shock: 0.0,
        gravity: Vec3::new(0.0, -G, 0.0),
        ..SimSettings::default()
    }
}

fn chain(points: Vec<Vec3>) -> HairAsset {
    let n = points.len() as u32;
    HairAsset::from_counts(points, &[n]).unwrap()
}

/// Times at which `signal` crosses zero going up (linear interpolation between samples).
fn upward_crossings(signal: &[(f32, f32)]) -> Vec<f32> {
    signal
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * (-w[0].1 / (w[1].1 - w[0].1)))
        .collect()
}

fn mean_period(crossings: &[f32]) -> f32 {
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f32
}

#[test]
fn a_two_vertex_strand_swings_with_the_pendulum_period() {
    let l = 20.0;
    let angle = 5f32.to_radians();
    let asset = chain(vec![
        Vec3::ZERO,
        Vec3::new(l * angle.sin(), -l * angle.cos(), 0.0),
    ]);
    let s = bare(60.0, 4, 1);
    let mut sim =
        Simulation::new(&asset, None, &s, &GuideChoice::Share(1.0), Rigid::IDENTITY).unwrap();
    let mut signal = Vec::new();
    for k in 0..60 * 6 {
        sim.step(Rigid::IDENTITY);
        signal.push(((k + 1) as f32 / 60.0, sim.guides().0[1].x));
    }
    let period = mean_period(&upward_crossings(&signal));
    let want = TAU * (l / G).sqrt();
    assert!(
        (period - want).abs() < 0.02 * want,
        "{period} s against 2π√(L/g) = {want} s"
    );
}

#[test]
fn a_hanging_chain_settles_straight_down_and_swings_with_its_first_mode() {
    let n = 33;
    let l = 30.0;
    let seg = l / (n - 1) as f32;
    // Rest: straight down, then tilted a little for the swing.
    let straight: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(0.0, -seg * i as f32, 0.0))
        .collect();
    let mut damped = bare(60.0, 4, 8);
    damped.damping = 4.0;
    let mut sim = Simulation::new(
        &chain(
            (0..n)
                .map(|i| Vec3::new(seg * i as f32 * 0.6, -seg * i as f32 * 0.8, 0.0))
                .collect(),
        ),
        None,
        &damped,
        &GuideChoice::Share(1.0),
        Rigid::IDENTITY,
    )
    .unwrap();
    for _ in 0..60 * 10 {
        sim.step(Rigid::IDENTITY);
    }
    let tip = sim.guides().0[n - 1];
    assert!(
        (tip - Vec3::new(0.0, -l, 0.0)).length() < 0.01 * l,
        "the chain's tip rests at {tip}, not at root − L·ĝ"
    );
    for (p, q) in sim.guides().0.iter().zip(&straight) {
        assert!(p.distance(*q) < 0.01 * l, "{p} against {q}");
    }
    // The first mode: a small tilt, released without damping.
    let angle = 3f32.to_radians();
    let tilted: Vec<Vec3> = (0..n)
        .map(|i| {
            Vec3::new(
                seg * i as f32 * angle.sin(),
                -seg * i as f32 * angle.cos(),
                0.0,
            )
        })
        .collect();
    let s = bare(60.0, 8, 16);
    let mut sim = Simulation::new(
        &chain(tilted),
        None,
        &s,
        &GuideChoice::Share(1.0),
        Rigid::IDENTITY,
    )
    .unwrap();
    let mut signal = Vec::new();
    for k in 0..60 * 8 {
        sim.step(Rigid::IDENTITY);
        // The chain's centre of mass sways with the first mode (higher modes barely move it).
        let mean_x: f32 = sim.guides().0.iter().map(|p| p.x).sum::<f32>() / n as f32;
        signal.push(((k + 1) as f32 / 60.0, mean_x));
    }
    let period = mean_period(&upward_crossings(&signal));
    let want = 5.22 * (l / G).sqrt();
    assert!(
        (period - want).abs() < 0.05 * want,
        "{period} s against 5.22·√(L/g) = {want} s"
    );
}

/// A curly groom on the generated head, with the head's mesh to collide with.
fn curly(strands: u32) -> (HairAsset, tress_hair::generate::TriMesh) {
    let mut p = Style::Curly.default_params();
    p.strands = strands;
    p.vertices = 16;
    p.seed = 3;
    let asset = generate(Style::Curly, &p).unwrap();
    (asset, head_for(Style::Curly).mesh(3))
}

#[test]
fn a_groom_at_rest_stays_put_at_every_iteration_count() {
    let (asset, mesh) = curly(200);
    let size = asset.bounds().size().length();
    for iterations in [1, 2, 3, 5, 8] {
        let s = SimSettings {
            iterations,
            gravity: Vec3::ZERO,
            ..SimSettings::default()
        };
        let mut sim = Simulation::new(
            &asset,
            Some(&mesh),
            &s,
            &GuideChoice::Share(0.25),
            Rigid::IDENTITY,
        )
        .unwrap();
        for _ in 0..600 {
            sim.step(Rigid::IDENTITY);
        }
        let drift = sim
            .positions()
            .iter()
            .zip(asset.positions())
            .map(|(a, b)| a.distance(*b))
            .fold(0.0f32, f32::max);
        assert!(
            drift < 1e-5 * size,
            "{iterations} iterations: drift {drift} of {size}"
        );
    }
}

/// Longest relative error of a segment's length against the rest asset.
fn length_error(sim: &Simulation, rest: &HairAsset) -> f32 {
    let p = sim.positions();
    let mut worst = 0.0f32;
    for s in 0..rest.strand_count() {
        let r = rest.strand_range(s);
        for i in r.start + 1..r.end {
            let l0 = rest.positions()[i].distance(rest.positions()[i - 1]);
            let l = p[i].distance(p[i - 1]);
            worst = worst.max((l - l0).abs() / l0);
        }
    }
    worst
}

#[test]
fn strands_keep_their_length_and_roots_stay_on_a_shaking_head() {
    let (asset, mesh) = curly(120);
    let s = SimSettings::default();
    let motion = MotionSpec {
        frequency: Some(3.0),
        ..MotionSpec::preset(Preset::Shake)
    };
    let pivot = head_for(Style::Curly).center;
    // Every strand simulated, then a quarter (the followers' roots rebuilt from the guides').
    for share in [1.0, 0.25] {
        let mut sim = Simulation::new(
            &asset,
            Some(&mesh),
            &s,
            &GuideChoice::Share(share),
            Rigid::IDENTITY,
        )
        .unwrap();
        let mut worst = 0.0f32;
        for k in 1..=120 {
            let head = motion.at(k as f32 / 60.0, pivot);
            sim.step(head);
            worst = worst.max(length_error(&sim, &asset));
            let p = sim.positions();
            for st in 0..asset.strand_count() {
                let root = asset.strand_range(st).start;
                let want = head.apply(asset.positions()[root]);
                assert!(
                    p[root].distance(want) < 1e-4,
                    "share {share}, step {k}: root {st} off the head"
                );
            }
        }
        if share == 1.0 {
            assert!(
                worst <= 0.005,
                "segment length error {worst} over a 3 Hz shake"
            );
        }
    }
}

#[test]
fn no_vertex_enters_the_head_through_a_fast_turn() {
    let (asset, mesh) = curly(150);
    let s = SimSettings::default();
    let pivot = head_for(Style::Curly).center;
    let motion = MotionSpec {
        amplitude: Some(90.0),
        frequency: Some(1.5),
        ..MotionSpec::preset(Preset::Turn)
    };
    let mut sim = Simulation::new(
        &asset,
        Some(&mesh),
        &s,
        &GuideChoice::Share(1.0),
        Rigid::IDENTITY,
    )
    .unwrap();
    let sdf = sim.colliders().sdf.clone().unwrap();
    let eps = 0.05 * sdf.cell;
    for k in 1..=90 {
        let head = motion.at(k as f32 / 60.0, pivot);
        sim.step(head);
        let inv = head.inverse();
        let (x, offsets, _) = sim.guides();
        for g in 0..offsets.len() - 1 {
            let strand = offsets[g] as usize..offsets[g + 1] as usize;
            for (i, p) in x[strand.clone()].iter().enumerate().skip(1) {
                let d = sdf.distance(inv.apply(*p));
                assert!(
                    d >= s.collision_margin - eps,
                    "step {k}: vertex {i} of strand {g} at distance {d}"
                );
            }
        }
    }
}

#[test]
fn the_state_at_a_time_does_not_depend_on_the_display_rate() {
    let (asset, mesh) = curly(60);
    let s = SimSettings::default();
    let pivot = head_for(Style::Curly).center;
    let motion = MotionSpec::preset(Preset::Nod);
    let run = |display_hz: f64| {
        let mut sim = Simulation::new(
            &asset,
            Some(&mesh),
            &s,
            &GuideChoice::Share(0.5),
            Rigid::IDENTITY,
        )
        .unwrap();
        let mut states = Vec::new();
        let mut frame = 0u64;
        loop {
            frame += 1;
            let t = frame as f64 / display_hz;
            if t > 1.0 + 1e-9 {
                break;
            }
            sim.advance_to(t, |t| motion.at(t, pivot));
            // Compare at the times both displays show: every 1/12 s.
            let twelfths = t * 12.0;
            if (twelfths - twelfths.round()).abs() < 1e-9 {
                states.push((twelfths.round() as u32, sim.steps(), sim.positions()));
            }
        }
        states
    };
    let a = run(60.0);
    let b = run(144.0);
    assert_eq!(a.len(), 12);
    assert_eq!(a, b);
}

#[test]
fn a_teleport_does_not_stretch_the_hair() {
    let (asset, mesh) = curly(80);
    let s = SimSettings::default();
    let mut sim = Simulation::new(
        &asset,
        Some(&mesh),
        &s,
        &GuideChoice::Share(1.0),
        Rigid::IDENTITY,
    )
    .unwrap();
    for _ in 0..30 {
        sim.step(Rigid::IDENTITY);
    }
    let far = Rigid::about(
        Vec3::ZERO,
        Quat::from_rotation_y(PI * 0.75),
        Vec3::new(300.0, 20.0, -100.0),
    );
    let report = sim.step(far);
    assert!(report.teleported);
    let stretch = length_error(&sim, &asset);
    assert!(stretch <= 0.01, "a segment stretched {stretch}");
    // The hair is on the head where it went.
    let root = asset.strand_range(0).start;
    assert!(sim.positions()[root].distance(far.apply(asset.positions()[root])) < 1e-3);
}

#[test]
fn two_runs_give_byte_identical_positions() {
    let (asset, mesh) = curly(100);
    let s = SimSettings {
        wind: tress_sim::Wind {
            strength: 200.0,
            ..tress_sim::Wind::default()
        },
        ..SimSettings::default()
    };
    let pivot = head_for(Style::Curly).center;
    let motion = MotionSpec::preset(Preset::Run);
    let run = || {
        let mut sim = Simulation::new(
            &asset,
            Some(&mesh),
            &s,
            &GuideChoice::Share(0.2),
            Rigid::IDENTITY,
        )
        .unwrap();
        sim.advance_to(1.0, |t| motion.at(t, pivot));
        sim.positions()
    };
    let a: Vec<[u32; 3]> = run()
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    let b: Vec<[u32; 3]> = run()
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    assert_eq!(a, b);
}

#[test]
fn wind_moves_the_hair_downwind() {
    let (asset, mesh) = curly(60);
    let calm = SimSettings::default();
    let windy = SimSettings {
        wind: tress_sim::Wind {
            direction: Vec3::X,
            strength: 300.0,
            turbulence: 0.2,
            drag: 4.0,
        },
        ..SimSettings::default()
    };
    let tip_x = |s: &SimSettings| {
        let mut sim = Simulation::new(
            &asset,
            Some(&mesh),
            s,
            &GuideChoice::Share(1.0),
            Rigid::IDENTITY,
        )
        .unwrap();
        sim.advance_to(2.0, |_| Rigid::IDENTITY);
        let p = sim.positions();
        (0..asset.strand_count())
            .map(|st| p[asset.strand_range(st).end - 1].x)
            .sum::<f32>()
            / asset.strand_count() as f32
    };
    let (a, b) = (tip_x(&calm), tip_x(&windy));
    assert!(b > a + 1.0, "tips at x {a} calm, {b} in the wind");
}
