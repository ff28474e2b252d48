//! The viewer's simulation controls as plain state, no GPU: on and off, pause, single step,
//! reset, the head's motion, the panel's setting edits and the head dragged with the mouse.
//! [`SimControls::apply`] turns what the user asked for into a [`Command`] for the session
//! ([`tress_render::session::Session::start_simulation`], `stop_simulation`), and each frame
//! [`SimControls::advance`] gives the simulated time to run to and [`SimControls::head`] where
//! each character's head is at any moment of it (for `Session::simulate_to_with`).
//!
//! Time: simulated seconds follow the frames' wall-clock intervals, each counted as at most
//! [`MAX_FRAME_DT`] so a stall (a slow frame, a window drag) does not run thousands of steps at
//! once. The session steps at the fixed `rate_hz` from its own accumulator, so the display rate
//! does not change the result. Paused, time stands still; Step runs exactly one step of
//! `1 / rate_hz` seconds.
//!
//! Settings: the session's simulation takes its settings at start, so a changed stiffness,
//! damping or wind starts the simulation again ([`Command::Restart`]): the hair back at rest on
//! the head where it is now, the clock and the head's motion going on from where they were. The
//! restarted simulation starts with the head held there ([`hold`]); later steps are moved by
//! [`SimControls::head`], so the session's own motion is only its start.
//!
//! The head: the chosen motion (a preset, the scene's `[head.motion]`, or still), then the
//! mouse's drag: a translation in the view plane and a yaw about the vertical axis through the
//! moving head's pivot. A frame's drag is spread over its steps, so a fast drag moves the head
//! smoothly however many steps the frame runs.

use glam::{EulerRot, Quat, Vec2, Vec3};
use tress_sim::{Keyframe, MotionSpec, Preset, Rigid, SimError, SimSettings};

/// The longest wall-clock interval a frame counts as, seconds.
pub(crate) const MAX_FRAME_DT: f64 = 0.1;

/// Radians of head yaw per pixel of drag (the orbit's rate).
pub(crate) const HEAD_RADIANS_PER_PIXEL: f32 = crate::orbit::RADIANS_PER_PIXEL;

/// The slider ranges: damping (per second), wind strength (world units a second: centimetres in
/// the scenes, so 0 to 20 m/s).
pub(crate) const DAMPING_MAX: f32 = 20.0;
/// See [`DAMPING_MAX`].
pub(crate) const WIND_MAX: f32 = 2000.0;

/// Which motion moves the head.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MotionChoice {
    /// The scene's `[head.motion]` (still without one).
    Scene,
    /// No motion (the mouse can still drag the head).
    Still,
    /// A preset with its defaults (turning about the scene's pivot if it gives one).
    Preset(Preset),
}

impl MotionChoice {
    /// Every choice, in the panel's order.
    pub(crate) const ALL: [MotionChoice; 6] = [
        MotionChoice::Scene,
        MotionChoice::Still,
        MotionChoice::Preset(Preset::Turn),
        MotionChoice::Preset(Preset::Nod),
        MotionChoice::Preset(Preset::Shake),
        MotionChoice::Preset(Preset::Run),
    ];

    /// The panel's name.
    pub(crate) fn name(self) -> &'static str {
        match self {
            MotionChoice::Scene => "the scene's",
            MotionChoice::Still => "still",
            MotionChoice::Preset(p) => Preset::NAMES[p as usize],
        }
    }

    /// The motion, given the scene's.
    pub(crate) fn spec(self, scene: Option<&MotionSpec>) -> MotionSpec {
        match self {
            MotionChoice::Scene => scene.cloned().unwrap_or_default(),
            MotionChoice::Still => MotionSpec::default(),
            MotionChoice::Preset(p) => MotionSpec {
                pivot: scene.and_then(|m| m.pivot),
                ..MotionSpec::preset(p)
            },
        }
    }
}

/// The settings the panel edits; the others are the scene's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SimEdit {
    /// `simulation.local_stiffness`, in [0, 1].
    pub(crate) local_stiffness: f32,
    /// `simulation.global_stiffness`, in [0, 1].
    pub(crate) global_stiffness: f32,
    /// `simulation.damping`, in [0, [`DAMPING_MAX`]].
    pub(crate) damping: f32,
    /// `simulation.wind.strength`, in [0, [`WIND_MAX`]].
    pub(crate) wind_strength: f32,
    /// `simulation.wind.turbulence`, in [0, 1].
    pub(crate) wind_turbulence: f32,
    /// The wind's heading about the vertical (y) axis, degrees in (-180, 180]: 0 blows towards
    /// +x, 90 towards +z.
    pub(crate) wind_angle_deg: f32,
}

/// `v` within `lo..=hi`; `fallback` when it is not a number.
fn clamp_finite(v: f32, lo: f32, hi: f32, fallback: f32) -> f32 {
    if v.is_finite() {
        v.clamp(lo, hi)
    } else {
        fallback
    }
}

/// `deg` wrapped into (-180, 180].
fn wrap_degrees(deg: f32) -> f32 {
    let w = (deg + 180.0).rem_euclid(360.0) - 180.0;
    if w == -180.0 { 180.0 } else { w }
}

/// The heading of `direction` about the y axis, degrees (0 without a horizontal part).
fn heading_deg(direction: Vec3) -> f32 {
    let h = Vec2::new(direction.x, direction.z);
    if h.length_squared() > 1e-12 {
        wrap_degrees(h.y.atan2(h.x).to_degrees())
    } else {
        0.0
    }
}

impl SimEdit {
    /// The edited values of `s`.
    pub(crate) fn from_settings(s: &SimSettings) -> SimEdit {
        SimEdit {
            local_stiffness: s.local_stiffness,
            global_stiffness: s.global_stiffness,
            damping: s.damping,
            wind_strength: s.wind.strength,
            wind_turbulence: s.wind.turbulence,
            wind_angle_deg: heading_deg(s.wind.direction),
        }
    }

    /// Every value in its range (not-a-number values take the defaults).
    pub(crate) fn clamped(self) -> SimEdit {
        let d = SimSettings::default();
        SimEdit {
            local_stiffness: clamp_finite(self.local_stiffness, 0.0, 1.0, d.local_stiffness),
            global_stiffness: clamp_finite(self.global_stiffness, 0.0, 1.0, d.global_stiffness),
            damping: clamp_finite(self.damping, 0.0, DAMPING_MAX, d.damping),
            wind_strength: clamp_finite(self.wind_strength, 0.0, WIND_MAX, d.wind.strength),
            wind_turbulence: clamp_finite(self.wind_turbulence, 0.0, 1.0, d.wind.turbulence),
            wind_angle_deg: if self.wind_angle_deg.is_finite() {
                wrap_degrees(self.wind_angle_deg)
            } else {
                0.0
            },
        }
    }

    /// `base` with these values (clamped), checked. A changed heading turns the base's wind
    /// direction about the y axis, keeping its vertical part; an unchanged one keeps it exactly.
    pub(crate) fn settings(&self, base: &SimSettings) -> Result<SimSettings, SimError> {
        let e = self.clamped();
        let mut s = base.clone();
        s.local_stiffness = e.local_stiffness;
        s.global_stiffness = e.global_stiffness;
        s.damping = e.damping;
        s.wind.strength = e.wind_strength;
        s.wind.turbulence = e.wind_turbulence;
        let d = base.wind.direction;
        if (wrap_degrees(e.wind_angle_deg - heading_deg(d))).abs() > 1e-3
            || Vec2::new(d.x, d.z).length_squared() <= 1e-12
        {
            let h = Vec2::new(d.x, d.z).length();
            let h = if h > 1e-6 { h } else { 1.0 };
            let (sin, cos) = e.wind_angle_deg.to_radians().sin_cos();
            let y = if d.y.is_finite() { d.y } else { 0.0 };
            s.wind.direction = Vec3::new(h * cos, y, h * sin);
        }
        s.validate()?;
        Ok(s)
    }
}

/// The mouse's move of the head: a yaw about the vertical axis through the head's pivot, then a
/// translation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct HeadDrag {
    /// World units.
    pub(crate) translation: Vec3,
    /// Radians about +y.
    pub(crate) yaw: f32,
}

impl HeadDrag {
    /// A drag of `(dx, dy)` pixels (y down) in the view plane: the head moves with the cursor,
    /// `units_per_pixel` world units a pixel along the screen's `right` and `up` (world space).
    pub(crate) fn moved(&mut self, dx: f32, dy: f32, right: Vec3, up: Vec3, units_per_pixel: f32) {
        self.translation += (right * dx - up * dy) * units_per_pixel;
    }

    /// A turning drag of `dx` pixels: dragging right turns the face (+z) towards +x.
    pub(crate) fn turned(&mut self, dx: f32) {
        self.yaw += dx * HEAD_RADIANS_PER_PIXEL;
    }

    /// A share `s` of the way from `a` to `b`.
    pub(crate) fn lerp(a: &HeadDrag, b: &HeadDrag, s: f32) -> HeadDrag {
        HeadDrag {
            translation: a.translation.lerp(b.translation, s),
            yaw: a.yaw + (b.yaw - a.yaw) * s,
        }
    }

    /// The transform: the yaw about `center`, then the translation.
    pub(crate) fn rigid(&self, center: Vec3) -> Rigid {
        Rigid::about(center, Quat::from_rotation_y(self.yaw), self.translation)
    }
}

/// A motion holding the head at `head` (a keyframe turning about the origin): what a restarted
/// simulation starts with, so its hair is put back at rest where the head is.
pub(crate) fn hold(head: Rigid) -> MotionSpec {
    let (z, y, x) = head.rotation.to_euler(EulerRot::ZYX);
    MotionSpec {
        pivot: Some(Vec3::ZERO),
        keyframes: vec![Keyframe {
            time: 0.0,
            translation: head.translation,
            rotation_deg: Vec3::new(x, y, z) * (180.0 / std::f32::consts::PI),
        }],
        ..MotionSpec::default()
    }
}

/// Steps the session has run by `t` seconds at `rate_hz` (its accumulator's rule).
pub(crate) fn steps_due(t: f64, rate_hz: f32) -> u64 {
    (t * f64::from(rate_hz) + 1e-9).floor().max(0.0) as u64
}

/// `dt` as a frame counts it: at most [`MAX_FRAME_DT`], nothing for a negative or not-a-number
/// interval.
pub(crate) fn frame_dt(dt: f64) -> f64 {
    if dt.is_finite() && dt > 0.0 {
        dt.min(MAX_FRAME_DT)
    } else {
        0.0
    }
}

/// What the user asks of the simulation.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum SimAction {
    /// Simulate (start at 0 s) or not (the hair back at rest).
    Enable(bool),
    /// Pause or run on.
    Pause(bool),
    /// One step of `1 / rate_hz` seconds (pausing first).
    Step,
    /// Start again at 0 s, the drag undone.
    Reset,
    /// Move the head this way (starts again at 0 s).
    Motion(MotionChoice),
    /// New values of the edited settings (applied on a slider's release).
    Edit(SimEdit),
}

/// What the session must do.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Command {
    /// Nothing.
    None,
    /// Start simulating at 0 s; then report the characters' pivots ([`SimControls::started`]).
    Start {
        /// Settings.
        settings: SimSettings,
        /// The chosen motion.
        motion: MotionSpec,
    },
    /// Start again with new settings, the head held where it is ([`hold`]); the clock goes on.
    Restart {
        /// Settings.
        settings: SimSettings,
        /// The head held.
        motion: MotionSpec,
    },
    /// Stop simulating.
    Stop,
}

/// The drag at both ends of the frame being simulated, and its local times.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Span {
    t0: f64,
    t1: f64,
    d0: HeadDrag,
    d1: HeadDrag,
}

/// The simulation's state in the viewer (see the module docs).
#[derive(Clone, Debug)]
pub(crate) struct SimControls {
    /// Whether the hair is simulated (the checkbox).
    pub(crate) enabled: bool,
    /// Whether time stands still.
    pub(crate) paused: bool,
    /// The head's motion.
    pub(crate) motion: MotionChoice,
    /// The panel's settings.
    pub(crate) edit: SimEdit,
    /// The scene's settings, which the edits change.
    base: SimSettings,
    /// The scene's `[head.motion]`.
    scene_motion: Option<MotionSpec>,
    /// The motion in use.
    spec: MotionSpec,
    /// Simulated seconds before the session's simulation last (re)started.
    offset: f64,
    /// Simulated seconds of the session's simulation.
    local: f64,
    /// The mouse's drag now.
    drag: HeadDrag,
    /// The frame being simulated.
    span: Span,
    /// Each character's pivot (from the session's first start).
    pivots: Vec<Vec3>,
}

impl SimControls {
    /// Off, with the scene's settings and motion.
    pub(crate) fn new(base: SimSettings, scene_motion: Option<MotionSpec>) -> SimControls {
        let motion = MotionChoice::Scene;
        SimControls {
            enabled: false,
            paused: false,
            motion,
            edit: SimEdit::from_settings(&base),
            spec: motion.spec(scene_motion.as_ref()),
            base,
            scene_motion,
            offset: 0.0,
            local: 0.0,
            drag: HeadDrag::default(),
            span: Span::default(),
            pivots: Vec::new(),
        }
    }

    /// New scene settings and motion (the panel's edits start from them); the state is kept.
    pub(crate) fn rebase(&mut self, base: SimSettings, scene_motion: Option<MotionSpec>) {
        self.edit = SimEdit::from_settings(&base);
        self.base = base;
        self.scene_motion = scene_motion;
        self.spec = self.motion.spec(self.scene_motion.as_ref());
    }

    /// Whether `base` and `scene_motion` are those in use.
    pub(crate) fn same_scene(&self, base: &SimSettings, scene_motion: Option<&MotionSpec>) -> bool {
        &self.base == base && self.scene_motion.as_ref() == scene_motion
    }

    /// The scene's settings with the panel's edits.
    pub(crate) fn settings(&self) -> Result<SimSettings, SimError> {
        self.edit.settings(&self.base)
    }

    /// Simulation steps a second.
    pub(crate) fn rate_hz(&self) -> f32 {
        self.base.rate_hz
    }

    /// Simulated seconds since the start.
    pub(crate) fn time(&self) -> f64 {
        self.offset + self.local
    }

    /// Simulated seconds of the session's simulation (since its last restart).
    #[cfg(test)]
    pub(crate) fn local_time(&self) -> f64 {
        self.local
    }

    /// The mouse's drag now.
    pub(crate) fn drag(&self) -> HeadDrag {
        self.drag
    }

    /// The head at 0 s, no drag, a start due.
    fn start(&mut self) -> Command {
        self.offset = 0.0;
        self.local = 0.0;
        self.drag = HeadDrag::default();
        self.span = Span::default();
        match self.settings() {
            Ok(settings) => Command::Start {
                settings,
                motion: self.spec.clone(),
            },
            // The edits are clamped and the scene's settings checked: only a scene whose own
            // settings fail comes here, and the session reports it the same way.
            Err(_) => Command::Start {
                settings: self.base.clone(),
                motion: self.spec.clone(),
            },
        }
    }

    /// Apply what the user asked (see [`SimAction`]).
    pub(crate) fn apply(&mut self, action: SimAction) -> Command {
        match action {
            SimAction::Enable(true) if !self.enabled => {
                self.enabled = true;
                self.paused = false;
                self.start()
            }
            SimAction::Enable(false) if self.enabled => {
                self.stopped();
                Command::Stop
            }
            SimAction::Enable(_) => Command::None,
            SimAction::Pause(p) => {
                self.paused = p;
                Command::None
            }
            SimAction::Step => {
                if self.enabled {
                    self.paused = true;
                    let rate = self.rate_hz();
                    self.local = (steps_due(self.local, rate) + 1) as f64 / f64::from(rate);
                }
                Command::None
            }
            SimAction::Reset if self.enabled => self.start(),
            SimAction::Reset => {
                self.offset = 0.0;
                self.local = 0.0;
                self.drag = HeadDrag::default();
                Command::None
            }
            SimAction::Motion(m) => {
                self.motion = m;
                self.spec = m.spec(self.scene_motion.as_ref());
                if self.enabled {
                    self.start()
                } else {
                    Command::None
                }
            }
            SimAction::Edit(e) => {
                self.edit = e.clamped();
                if !self.enabled {
                    return Command::None;
                }
                let settings = match self.settings() {
                    Ok(s) => s,
                    Err(_) => return Command::None,
                };
                // The head where the hair last saw it, held; the clock goes on from there.
                let head = self.head(0, self.local as f32);
                self.offset += self.local;
                self.local = 0.0;
                self.span = Span {
                    t0: 0.0,
                    t1: 0.0,
                    d0: self.span.d1,
                    d1: self.span.d1,
                };
                Command::Restart {
                    settings,
                    motion: hold(head),
                }
            }
        }
    }

    /// The session started ([`Command::Start`]): each character's pivot.
    pub(crate) fn started(&mut self, pivots: Vec<Vec3>) {
        self.pivots = pivots;
    }

    /// The session's simulation stopped (asked, or failed): off, the clock and drag at 0.
    pub(crate) fn stopped(&mut self) {
        self.enabled = false;
        self.paused = false;
        self.offset = 0.0;
        self.local = 0.0;
        self.drag = HeadDrag::default();
        self.span = Span::default();
    }

    /// A frame `dt` seconds after the last: the session's time to simulate to (local), `None`
    /// when off. Time runs unless paused; `dt` counts as [`frame_dt`] says.
    pub(crate) fn advance(&mut self, dt: f64) -> Option<f64> {
        if !self.enabled {
            return None;
        }
        let t0 = self.local;
        if !self.paused {
            self.local += frame_dt(dt);
        }
        self.span = Span {
            t0,
            t1: self.local,
            d0: self.span.d1,
            d1: self.drag,
        };
        Some(self.local)
    }

    /// Shift + drag: the head moves in the view plane (see [`HeadDrag::moved`]). Ignored when
    /// off; returns whether it was taken.
    pub(crate) fn drag_move(
        &mut self,
        dx: f32,
        dy: f32,
        right: Vec3,
        up: Vec3,
        units_per_pixel: f32,
    ) -> bool {
        if self.enabled {
            self.drag.moved(dx, dy, right, up, units_per_pixel);
        }
        self.enabled
    }

    /// Ctrl + drag: the head turns (see [`HeadDrag::turned`]). Ignored when off; returns whether
    /// it was taken.
    pub(crate) fn drag_turn(&mut self, dx: f32) -> bool {
        if self.enabled {
            self.drag.turned(dx);
        }
        self.enabled
    }

    /// Where `character`'s head is at `local` seconds of the session's simulation (within the
    /// frame last given by [`SimControls::advance`]): the motion, then the drag (spread across
    /// the frame) about the first character's moving pivot.
    pub(crate) fn head(&self, character: usize, local: f32) -> Rigid {
        let t = (self.offset + f64::from(local)) as f32;
        let p0 = self.pivots.first().copied().unwrap_or(Vec3::ZERO);
        let pk = self.pivots.get(character).copied().unwrap_or(p0);
        let motion = self.spec.at(t, pk);
        let center = self.spec.at(t, p0).apply(self.spec.pivot.unwrap_or(p0));
        let span = self.span.t1 - self.span.t0;
        let s = if span > 0.0 {
            ((f64::from(local) - self.span.t0) / span).clamp(0.0, 1.0) as f32
        } else {
            1.0
        };
        HeadDrag::lerp(&self.span.d0, &self.span.d1, s)
            .rigid(center)
            .then(&motion)
    }
}

#[cfg(test)]
mod gpu_tests;
#[cfg(test)]
mod tests;
