//! The wind's air velocity at a point and time, and the drag it puts on a strand.
//!
//! Turbulence is a smooth, deterministic field: each component a mean of three sine waves
//! across space and time (wavelengths of tens of world units, periods of a few seconds), the same
//! in the WGSL twin. The drag acts only across the strand (a strand moving along its own length
//! meets no air), `drag · (u − (u·t̂) t̂)` with `u` the air's velocity relative to the vertex.

use glam::Vec3;

use crate::settings::Wind;

/// A smooth field in [-1, 1] of a point and a time; `seed` picks one of several fields.
pub fn noise(p: Vec3, t: f32, seed: f32) -> f32 {
    let a = (p.x * 0.11 + p.y * 0.05 + t * 1.3 + seed * 1.7).sin();
    let b = (p.y * 0.09 - p.z * 0.13 + t * 0.9 + seed * 2.9).sin();
    let c = (p.z * 0.07 + p.x * 0.06 - t * 1.7 + seed * 4.1).sin();
    (a + b + c) / 3.0
}

/// The air's velocity at `p` (world space) at `t` seconds.
pub fn air_velocity(wind: &Wind, p: Vec3, t: f32) -> Vec3 {
    if wind.strength <= 0.0 {
        return Vec3::ZERO;
    }
    let d = wind.direction.normalize_or_zero();
    let gust = noise(p, t, 0.0);
    let side = Vec3::new(noise(p, t, 1.0), noise(p, t, 2.0), noise(p, t, 3.0));
    wind.strength * (d * (1.0 + wind.turbulence * gust) + side * (0.5 * wind.turbulence))
}

/// The wind's acceleration of a vertex moving at `velocity` whose strand runs along `tangent`
/// (unit, or zero for none: then the whole relative velocity acts).
pub fn drag(wind: &Wind, air: Vec3, velocity: Vec3, tangent: Vec3) -> Vec3 {
    let u = air - velocity;
    wind.drag * (u - tangent * u.dot(tangent))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wind_blows_its_way_on_average_and_only_across_the_strand() {
        let wind = Wind {
            direction: Vec3::new(2.0, 0.0, 0.0),
            strength: 100.0,
            turbulence: 0.5,
            drag: 2.0,
        };
        let mut mean = Vec3::ZERO;
        for i in 0..1000 {
            let f = i as f32;
            mean += air_velocity(&wind, Vec3::new(f * 1.3, f * 0.7, -f), f * 0.037);
        }
        mean /= 1000.0;
        assert!(
            (mean.x - 100.0).abs() < 10.0 && mean.y.abs() < 10.0,
            "{mean}"
        );
        // Along the strand, no drag.
        let a = drag(&wind, Vec3::new(50.0, 0.0, 0.0), Vec3::ZERO, Vec3::X);
        assert_eq!(a, Vec3::ZERO);
        let a = drag(&wind, Vec3::new(50.0, 0.0, 0.0), Vec3::ZERO, Vec3::Y);
        assert_eq!(a, Vec3::new(100.0, 0.0, 0.0));
        let calm = Wind::default();
        assert_eq!(air_velocity(&calm, Vec3::ONE, 1.0), Vec3::ZERO);
    }
}
