//! The head's motion: a rigid transform a moment, from a preset or keyframes (`[head.motion]`).

use std::f32::consts::TAU;

use glam::{EulerRot, Quat, Vec3};
use serde::{Deserialize, Serialize};

use crate::SimError;

/// A rigid transform: rotate, then translate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    /// Rotation.
    pub rotation: Quat,
    /// Translation, applied after the rotation.
    pub translation: Vec3,
}

impl Default for Rigid {
    fn default() -> Self {
        Rigid::IDENTITY
    }
}

impl Rigid {
    /// No motion.
    pub const IDENTITY: Rigid = Rigid {
        rotation: Quat::IDENTITY,
        translation: Vec3::ZERO,
    };

    /// A rotation by `rotation` about `pivot`, then a translation.
    pub fn about(pivot: Vec3, rotation: Quat, translation: Vec3) -> Rigid {
        Rigid {
            rotation,
            translation: pivot - rotation * pivot + translation,
        }
    }

    /// `p` moved.
    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.rotation * p + self.translation
    }

    /// A direction turned.
    pub fn turn(&self, v: Vec3) -> Vec3 {
        self.rotation * v
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Rigid {
        let r = self.rotation.inverse();
        Rigid {
            rotation: r,
            translation: -(r * self.translation),
        }
    }

    /// `self` after `other`: `p ↦ self(other(p))`.
    pub fn then(&self, other: &Rigid) -> Rigid {
        Rigid {
            rotation: (self.rotation * other.rotation).normalize(),
            translation: self.rotation * other.translation + self.translation,
        }
    }

    /// The transform a share `t` of the way from `a` to `b` (slerp and lerp).
    pub fn lerp(a: &Rigid, b: &Rigid, t: f32) -> Rigid {
        Rigid {
            rotation: a.rotation.slerp(b.rotation, t).normalize(),
            translation: a.translation.lerp(b.translation, t),
        }
    }
}

/// A head motion preset.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// Looking left and right: a rotation about the vertical axis (default 60°, 0.5 Hz).
    Turn,
    /// Nodding: a rotation about the sideways axis (default 20°, 1 Hz).
    Nod,
    /// Shaking the head: a fast rotation about the vertical axis (default 30°, 3 Hz).
    Shake,
    /// Running: the head bobs up and down twice a stride, sways and leans (default 2.5 strides
    /// a second, 3 units of bob).
    Run,
}

impl Preset {
    /// Every preset's name.
    pub const NAMES: [&'static str; 4] = ["turn", "nod", "shake", "run"];

    /// The default (amplitude in degrees, or units of bob for `run`; frequency in Hz).
    pub fn defaults(self) -> (f32, f32) {
        match self {
            Preset::Turn => (60.0, 0.5),
            Preset::Nod => (20.0, 1.0),
            Preset::Shake => (30.0, 3.0),
            Preset::Run => (3.0, 2.5),
        }
    }
}

impl std::str::FromStr for Preset {
    type Err = SimError;
    fn from_str(s: &str) -> Result<Self, SimError> {
        match s {
            "turn" => Ok(Preset::Turn),
            "nod" => Ok(Preset::Nod),
            "shake" => Ok(Preset::Shake),
            "run" => Ok(Preset::Run),
            _ => Err(SimError::setting(
                "head.motion.preset",
                format!("unknown preset `{s}` (one of {})", Preset::NAMES.join(", ")),
            )),
        }
    }
}

/// One keyframe: where the head is at `time`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    /// Seconds.
    pub time: f32,
    /// Translation.
    #[serde(default)]
    pub translation: Vec3,
    /// Rotation about the pivot as Euler angles in degrees (applied X, then Y, then Z).
    #[serde(default)]
    pub rotation_deg: Vec3,
}

/// `[head.motion]`: a preset or keyframes (not both); the rotations turn about `pivot`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MotionSpec {
    /// `turn`, `nod`, `shake` or `run`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preset: Option<Preset>,
    /// The preset's amplitude: degrees (units of bob for `run`); default: the preset's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f32>,
    /// The preset's frequency in Hz; default: the preset's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency: Option<f32>,
    /// The point rotations turn about; default: the head's centre.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pivot: Option<Vec3>,
    /// Keyframes in time order; the head holds the first before it and the last after it.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub keyframes: Vec<Keyframe>,
}

impl MotionSpec {
    /// A preset with its defaults.
    pub fn preset(preset: Preset) -> MotionSpec {
        MotionSpec {
            preset: Some(preset),
            ..MotionSpec::default()
        }
    }

    /// Whether the head moves at all.
    pub fn is_still(&self) -> bool {
        self.preset.is_none() && self.keyframes.is_empty()
    }

    /// Check the values; errors name the key.
    pub fn validate(&self) -> Result<(), SimError> {
        if self.preset.is_some() && !self.keyframes.is_empty() {
            return Err(SimError::setting(
                "head.motion",
                "give a preset or keyframes, not both",
            ));
        }
        for (key, v) in [("amplitude", self.amplitude), ("frequency", self.frequency)] {
            if let Some(v) = v
                && (!v.is_finite() || v < 0.0)
            {
                return Err(SimError::setting(
                    &format!("head.motion.{key}"),
                    format!("must be finite and at least 0, got {v}"),
                ));
            }
        }
        if self.pivot.is_some_and(|p| !p.is_finite()) {
            return Err(SimError::setting("head.motion.pivot", "must be finite"));
        }
        let mut last = f32::NEG_INFINITY;
        for (i, k) in self.keyframes.iter().enumerate() {
            if !k.time.is_finite() || k.time <= last {
                return Err(SimError::setting(
                    &format!("head.motion.keyframes[{i}].time"),
                    format!(
                        "must be finite and after the previous keyframe's, got {}",
                        k.time
                    ),
                ));
            }
            if !k.translation.is_finite() || !k.rotation_deg.is_finite() {
                return Err(SimError::setting(
                    &format!("head.motion.keyframes[{i}]"),
                    "translation and rotation_deg must be finite",
                ));
            }
            last = k.time;
        }
        Ok(())
    }

    /// The head's transform at `t` seconds, turning about `pivot` unless the spec gives one.
    pub fn at(&self, t: f32, pivot: Vec3) -> Rigid {
        let pivot = self.pivot.unwrap_or(pivot);
        if let Some(preset) = self.preset {
            let (a0, f0) = preset.defaults();
            let a = self.amplitude.unwrap_or(a0);
            let f = self.frequency.unwrap_or(f0);
            let phase = TAU * f * t;
            let (rotation, translation) = match preset {
                Preset::Turn | Preset::Shake => (
                    Quat::from_rotation_y(a.to_radians() * phase.sin()),
                    Vec3::ZERO,
                ),
                Preset::Nod => (
                    Quat::from_rotation_x(a.to_radians() * phase.sin()),
                    Vec3::ZERO,
                ),
                Preset::Run => {
                    // Two bobs a stride, a sway of the shoulders once a stride, a slight lean.
                    let bob = a * (2.0 * phase).sin().abs();
                    let sway = Quat::from_rotation_z(0.05 * phase.sin());
                    let lean = Quat::from_rotation_x(0.08 * (2.0 * phase).cos());
                    (sway * lean, Vec3::new(0.0, bob, 0.0))
                }
            };
            return Rigid::about(pivot, rotation, translation);
        }
        let keys = &self.keyframes;
        let pose = |k: &Keyframe| {
            let r = k.rotation_deg;
            let rotation = Quat::from_euler(
                EulerRot::ZYX,
                r.z.to_radians(),
                r.y.to_radians(),
                r.x.to_radians(),
            );
            Rigid::about(pivot, rotation, k.translation)
        };
        match keys.iter().position(|k| k.time > t) {
            None => keys.last().map_or(Rigid::IDENTITY, pose),
            Some(0) => pose(&keys[0]),
            Some(i) => {
                let (a, b) = (&keys[i - 1], &keys[i]);
                Rigid::lerp(&pose(a), &pose(b), (t - a.time) / (b.time - a.time))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_transforms_compose_and_invert() {
        let a = Rigid::about(
            Vec3::new(1.0, 2.0, 3.0),
            Quat::from_rotation_y(0.7),
            Vec3::X,
        );
        let b = Rigid::about(Vec3::ZERO, Quat::from_rotation_x(-0.3), Vec3::Z * 2.0);
        let p = Vec3::new(0.3, -1.0, 4.0);
        assert!((a.then(&b).apply(p) - a.apply(b.apply(p))).length() < 1e-5);
        assert!((a.inverse().apply(a.apply(p)) - p).length() < 1e-5);
        // A rotation about the pivot keeps the pivot in place.
        assert!((a.apply(Vec3::new(1.0, 2.0, 3.0)) - Vec3::new(2.0, 2.0, 3.0)).length() < 1e-5);
    }

    #[test]
    fn presets_and_keyframes_move_the_head_as_specified() {
        let shake = MotionSpec::preset(Preset::Shake);
        // A quarter period of 3 Hz: the full 30°.
        let r = shake.at(1.0 / 12.0, Vec3::ZERO);
        assert!((r.rotation.angle_between(Quat::IDENTITY) - 30f32.to_radians()).abs() < 1e-4);
        assert_eq!(shake.at(0.0, Vec3::ZERO), Rigid::IDENTITY);
        let keys = MotionSpec {
            keyframes: vec![
                Keyframe {
                    time: 0.0,
                    translation: Vec3::ZERO,
                    rotation_deg: Vec3::ZERO,
                },
                Keyframe {
                    time: 2.0,
                    translation: Vec3::new(10.0, 0.0, 0.0),
                    rotation_deg: Vec3::new(0.0, 90.0, 0.0),
                },
            ],
            ..MotionSpec::default()
        };
        keys.validate().unwrap();
        let mid = keys.at(1.0, Vec3::ZERO);
        assert!((mid.translation - Vec3::new(5.0, 0.0, 0.0)).length() < 1e-4);
        assert!((mid.rotation.angle_between(Quat::IDENTITY) - 45f32.to_radians()).abs() < 1e-4);
        assert_eq!(keys.at(5.0, Vec3::ZERO), keys.at(2.0, Vec3::ZERO));
        let mut both = keys.clone();
        both.preset = Some(Preset::Nod);
        assert!(
            both.validate()
                .unwrap_err()
                .to_string()
                .contains("head.motion")
        );
    }
}
