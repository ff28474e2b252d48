//! The controls' behaviour: time, pause and step, reset, the drag, settings edits.

use super::*;

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-3
}

fn running() -> SimControls {
    let mut c = SimControls::new(SimSettings::default(), None);
    assert!(matches!(
        c.apply(SimAction::Enable(true)),
        Command::Start { .. }
    ));
    c.started(vec![Vec3::new(0.0, 10.0, 0.0)]);
    c
}

#[test]
fn enabling_starts_at_zero_and_disabling_stops() {
    let mut c = SimControls::new(SimSettings::default(), None);
    assert_eq!(c.advance(0.05), None, "off: no time to simulate to");
    match c.apply(SimAction::Enable(true)) {
        Command::Start { settings, motion } => {
            assert_eq!(settings, SimSettings::default());
            assert!(motion.is_still());
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(c.apply(SimAction::Enable(true)), Command::None);
    assert_eq!(c.advance(0.05), Some(0.05));
    assert_eq!(c.apply(SimAction::Enable(false)), Command::Stop);
    assert!(!c.enabled);
    assert_eq!(c.time(), 0.0);
    assert_eq!(c.apply(SimAction::Enable(false)), Command::None);
}

#[test]
fn time_follows_the_clock_with_each_frame_clamped() {
    let mut c = running();
    assert_eq!(c.advance(0.02), Some(0.02));
    // A two-second stall counts as 0.1 s; a clock that went back or is broken counts nothing.
    assert!((c.advance(2.0).unwrap() - 0.12).abs() < 1e-12);
    assert!((c.advance(-1.0).unwrap() - 0.12).abs() < 1e-12);
    assert!((c.advance(f64::NAN).unwrap() - 0.12).abs() < 1e-12);
    assert_eq!(frame_dt(0.25), MAX_FRAME_DT);
    assert_eq!(frame_dt(0.01), 0.01);
}

#[test]
fn the_display_rate_does_not_change_the_steps_run() {
    // One second at 30, 60 and 144 frames a second reaches the same step count.
    for fps in [30u32, 60, 144] {
        let mut c = running();
        let mut t = 0.0;
        for _ in 0..fps {
            t = c.advance(1.0 / f64::from(fps)).unwrap();
        }
        assert_eq!(steps_due(t, c.rate_hz()), 60, "{fps} fps");
    }
}

#[test]
fn pause_stops_time_and_step_runs_exactly_one_step() {
    let mut c = running();
    c.advance(0.1);
    let t = c.advance(0.013).unwrap();
    assert_eq!(c.apply(SimAction::Pause(true)), Command::None);
    assert_eq!(c.advance(0.05), Some(t), "paused: time stands still");
    let rate = c.rate_hz();
    let n = steps_due(t, rate);
    assert_eq!(n, 6, "0.113 s at 60 Hz");
    // Off the step grid: a step ends at the next step's time.
    c.apply(SimAction::Step);
    let t1 = c.advance(0.05).unwrap();
    assert!((t1 - 7.0 / 60.0).abs() < 1e-12);
    assert_eq!(steps_due(t1, rate), n + 1);
    // On the grid: exactly 1/rate_hz a step.
    let mut last = t1;
    for k in 2..6 {
        c.apply(SimAction::Step);
        let t2 = c.advance(0.05).unwrap();
        assert!((t2 - last - 1.0 / f64::from(rate)).abs() < 1e-12);
        assert_eq!(steps_due(t2, rate), n + k);
        last = t2;
    }
    assert!(c.paused);
    c.apply(SimAction::Pause(false));
    assert!((c.advance(0.05).unwrap() - last - 0.05).abs() < 1e-12);
    // Step pauses a running simulation; it does nothing when off.
    c.apply(SimAction::Step);
    assert!(c.paused);
    let mut off = SimControls::new(SimSettings::default(), None);
    off.apply(SimAction::Step);
    assert_eq!(off.time(), 0.0);
}

#[test]
fn reset_returns_to_zero_and_undoes_the_drag() {
    let mut c = running();
    c.advance(0.08);
    c.drag_move(10.0, 0.0, Vec3::X, Vec3::Y, 1.0);
    match c.apply(SimAction::Reset) {
        Command::Start { .. } => {}
        other => panic!("{other:?}"),
    }
    assert_eq!(c.time(), 0.0);
    assert_eq!(c.drag(), HeadDrag::default());
    assert_eq!(c.advance(0.0), Some(0.0));
    assert!(c.enabled);
}

#[test]
fn a_drag_moves_the_head_with_the_cursor() {
    let mut c = running();
    let (right, up) = (Vec3::new(0.0, 0.0, -1.0), Vec3::Y);
    // 30 pixels right and 10 down at 0.5 units a pixel.
    assert!(c.drag_move(30.0, 10.0, right, up, 0.5));
    assert!(close(c.drag().translation, Vec3::new(0.0, -5.0, -15.0)));
    c.advance(0.0);
    let head = c.head(0, 0.0);
    assert!(close(head.apply(Vec3::ZERO), Vec3::new(0.0, -5.0, -15.0)));
    // Turning: 157 pixels ≈ 90° about the pivot; the pivot stays, the face (+z) turns to +x.
    let mut c = running();
    assert!(c.drag_turn(std::f32::consts::FRAC_PI_2 / HEAD_RADIANS_PER_PIXEL));
    c.advance(0.0);
    let head = c.head(0, 0.0);
    let pivot = Vec3::new(0.0, 10.0, 0.0);
    assert!(close(head.apply(pivot), pivot));
    assert!(close(head.apply(pivot + Vec3::Z), pivot + Vec3::X));
    // Off, a drag is not taken.
    let mut off = SimControls::new(SimSettings::default(), None);
    assert!(!off.drag_move(5.0, 5.0, Vec3::X, Vec3::Y, 1.0));
    assert!(!off.drag_turn(5.0));
    assert_eq!(off.drag(), HeadDrag::default());
}

#[test]
fn a_dragged_head_stays_under_the_cursor() {
    // A head at the orbit's target, dragged 40 pixels right and 25 down in a 640x360 view,
    // projects that far from the centre.
    let orbit = crate::orbit::OrbitCamera::new(
        Vec3::new(32.0, 4.0, 76.0),
        Vec3::new(0.0, -10.0, 0.0),
        Vec3::Y,
        35f32.to_radians(),
        1.0,
        500.0,
    );
    let (right, up, units_per_pixel) = orbit.view_plane(360);
    let mut drag = HeadDrag::default();
    drag.moved(40.0, 25.0, right, up, units_per_pixel);
    let moved = drag.rigid(orbit.target).apply(orbit.target);
    let clip = orbit.camera([640, 360]).clip_from_world() * moved.extend(1.0);
    let (px, py) = (clip.x / clip.w * 320.0, -clip.y / clip.w * 180.0);
    assert!(
        (px - 40.0).abs() < 0.05 && (py - 25.0).abs() < 0.05,
        "{px} {py}"
    );
}

#[test]
fn a_frames_drag_is_spread_over_its_steps() {
    let mut c = running();
    c.advance(0.05);
    c.drag_move(10.0, 0.0, Vec3::X, Vec3::Y, 1.0);
    let t = c.advance(0.05).unwrap();
    // Halfway through the frame, half the drag; at its end, all of it.
    let mid = c.head(0, (t - 0.025) as f32);
    assert!(close(mid.translation, Vec3::new(5.0, 0.0, 0.0)), "{mid:?}");
    assert!(close(c.head(0, t as f32).translation, Vec3::X * 10.0));
    // The next frame starts where this one ended.
    let t2 = c.advance(0.05).unwrap();
    assert!(close(
        c.head(0, (t2 - 0.04) as f32).translation,
        Vec3::X * 10.0
    ));
}

#[test]
fn the_head_follows_the_motion_then_the_drag() {
    let mut c = running();
    c.apply(SimAction::Motion(MotionChoice::Preset(Preset::Turn)));
    let pivot = Vec3::new(0.0, 10.0, 0.0);
    c.started(vec![pivot]);
    c.drag_move(0.0, -4.0, Vec3::X, Vec3::Y, 1.0);
    // Half a second of a 0.5 Hz turn: a quarter period, the full 60°.
    for _ in 0..5 {
        c.advance(0.1);
    }
    let t = c.local_time() as f32;
    let head = c.head(0, t);
    let turn = MotionSpec::preset(Preset::Turn).at(t, pivot);
    let p = pivot + Vec3::new(1.0, 2.0, 3.0);
    assert!(close(head.apply(p), turn.apply(p) + Vec3::Y * 4.0));
    assert!((head.rotation.angle_between(Quat::IDENTITY) - 60f32.to_radians()).abs() < 1e-3);
}

#[test]
fn an_edit_restarts_with_the_head_held_and_the_clock_going_on() {
    let mut c = running();
    c.apply(SimAction::Motion(MotionChoice::Preset(Preset::Nod)));
    c.started(vec![Vec3::new(0.0, 10.0, 0.0)]);
    c.drag_turn(40.0);
    c.drag_move(3.0, 1.0, Vec3::X, Vec3::Y, 2.0);
    for _ in 0..4 {
        c.advance(0.07);
    }
    let before = c.head(0, c.local_time() as f32);
    let time = c.time();
    let mut edit = c.edit;
    edit.wind_strength = 300.0;
    edit.local_stiffness = 0.5;
    let Command::Restart { settings, motion } = c.apply(SimAction::Edit(edit)) else {
        panic!("an edit while simulating restarts");
    };
    assert_eq!(settings.wind.strength, 300.0);
    assert_eq!(settings.local_stiffness, 0.5);
    motion.validate().unwrap();
    // The restarted simulation starts with the head where it was...
    let held = motion.at(0.0, Vec3::new(7.0, -3.0, 2.0));
    let p = Vec3::new(1.0, 12.0, -2.0);
    assert!(close(held.apply(p), before.apply(p)), "{held:?} {before:?}");
    // ... the clock goes on, and the head keeps moving from there.
    assert!((c.time() - time).abs() < 1e-12);
    assert_eq!(c.local_time(), 0.0);
    assert!(close(c.head(0, 0.0).apply(p), before.apply(p)));
    c.advance(0.05);
    let later = c.head(0, 0.05);
    let nod = MotionSpec::preset(Preset::Nod).at(time as f32 + 0.05, Vec3::new(0.0, 10.0, 0.0));
    assert!((later.rotation.angle_between(nod.rotation) - 0.4).abs() < 1e-3);
    // Off, an edit is kept for the next start.
    let mut off = SimControls::new(SimSettings::default(), None);
    assert_eq!(off.apply(SimAction::Edit(edit)), Command::None);
    match off.apply(SimAction::Enable(true)) {
        Command::Start { settings, .. } => assert_eq!(settings.wind.strength, 300.0),
        other => panic!("{other:?}"),
    }
}

#[test]
fn edits_give_checked_settings_with_values_clamped() {
    let base = SimSettings::default();
    let wild = SimEdit {
        local_stiffness: 1.7,
        global_stiffness: -0.3,
        damping: f32::NAN,
        wind_strength: 1e9,
        wind_turbulence: 2.0,
        wind_angle_deg: 450.0,
    };
    let s = wild.settings(&base).unwrap();
    s.validate().unwrap();
    assert_eq!(s.local_stiffness, 1.0);
    assert_eq!(s.global_stiffness, 0.0);
    assert_eq!(s.damping, base.damping);
    assert_eq!(s.wind.strength, WIND_MAX);
    assert_eq!(s.wind.turbulence, 1.0);
    // 450° is 90°: towards +z.
    assert!(close(s.wind.direction, Vec3::Z));
    assert_eq!(wild.clamped().wind_angle_deg, 90.0);
    assert_eq!(wrap_degrees(-180.0), 180.0);
    assert_eq!(wrap_degrees(-190.0), 170.0);
    // The other settings stay the scene's.
    assert_eq!(s.rate_hz, base.rate_hz);
    assert_eq!(s.gravity, base.gravity);
}

#[test]
fn the_wind_heading_turns_the_direction_about_the_vertical() {
    let mut base = SimSettings::default();
    base.wind.direction = Vec3::new(2.0, 1.0, 0.0);
    let mut e = SimEdit::from_settings(&base);
    assert_eq!(e.wind_angle_deg, 0.0);
    // Unchanged: the scene's direction exactly (not normalized, its tilt kept).
    assert_eq!(
        e.settings(&base).unwrap().wind.direction,
        base.wind.direction
    );
    e.wind_angle_deg = -90.0;
    let d = e.settings(&base).unwrap().wind.direction;
    assert!(close(d, Vec3::new(0.0, 1.0, -2.0)), "{d}");
    // Straight down: a heading gives a horizontal part.
    base.wind.direction = Vec3::new(0.0, -1.0, 0.0);
    e.wind_angle_deg = 180.0;
    let d = e.settings(&base).unwrap().wind.direction;
    assert!(close(d, Vec3::new(-1.0, -1.0, 0.0)), "{d}");
}

#[test]
fn motions_come_from_the_choice_and_the_scene() {
    let scene = MotionSpec {
        pivot: Some(Vec3::new(1.0, 2.0, 3.0)),
        ..MotionSpec::preset(Preset::Nod)
    };
    assert_eq!(MotionChoice::Scene.spec(Some(&scene)), scene);
    assert!(MotionChoice::Scene.spec(None).is_still());
    assert!(MotionChoice::Still.spec(Some(&scene)).is_still());
    let run = MotionChoice::Preset(Preset::Run).spec(Some(&scene));
    assert_eq!(run.preset, Some(Preset::Run));
    assert_eq!(run.pivot, scene.pivot);
    let names: Vec<_> = MotionChoice::ALL.iter().map(|m| m.name()).collect();
    assert_eq!(
        names,
        ["the scene's", "still", "turn", "nod", "shake", "run"]
    );
}

#[test]
fn a_held_head_is_the_head_given() {
    for head in [
        Rigid::IDENTITY,
        Rigid::about(
            Vec3::new(0.0, 10.0, 0.0),
            Quat::from_euler(EulerRot::XYZ, 0.3, -1.1, 0.2),
            Vec3::new(5.0, -2.0, 1.0),
        ),
        Rigid::about(Vec3::ONE, Quat::from_rotation_y(2.9), Vec3::ZERO),
    ] {
        let spec = hold(head);
        spec.validate().unwrap();
        for t in [0.0, 3.0] {
            let h = spec.at(t, Vec3::new(9.0, 9.0, 9.0));
            for p in [Vec3::ZERO, Vec3::new(10.0, 20.0, -5.0)] {
                assert!(close(h.apply(p), head.apply(p)), "{h:?} {head:?}");
            }
        }
    }
}

#[test]
fn a_new_scene_resets_the_edits() {
    let mut c = running();
    let mut e = c.edit;
    e.damping = 7.0;
    c.apply(SimAction::Edit(e));
    let base = SimSettings {
        damping: 3.0,
        ..SimSettings::default()
    };
    assert!(!c.same_scene(&base, None));
    c.rebase(base.clone(), Some(MotionSpec::preset(Preset::Shake)));
    assert!(c.same_scene(&base, Some(&MotionSpec::preset(Preset::Shake))));
    assert_eq!(c.edit.damping, 3.0);
    assert_eq!(c.settings().unwrap().damping, 3.0);
    // The scene's motion is the one in use when it is chosen.
    match c.apply(SimAction::Reset) {
        Command::Start { motion, .. } => assert_eq!(motion.preset, Some(Preset::Shake)),
        other => panic!("{other:?}"),
    }
}
