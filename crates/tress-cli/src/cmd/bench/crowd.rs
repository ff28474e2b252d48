//! The `characters` sweep's scenes: the hybrid paper's claim that the raymarcher "allows twice
//! the number of game characters to be on the screen at once, for the same time budget"
//! (Jansson et al. 2019, §1), measured with copies of a scene's hair spread in depth.

use glam::Vec3;
use tress_scene::Scene;

use super::report::Row;

/// `scene` with `n` characters: its first `[[hair]]` entry (with its generated head, if it has
/// one) and `n - 1` copies of it, each placed half a camera distance farther along the view
/// direction than the one before, in turn centred, to the left and to the right of the view
/// (so none hides another), within the frame. Its other entries are dropped. `None` without
/// hair.
pub(crate) fn crowd(scene: &Scene, n: u32) -> Option<Scene> {
    let first = scene.hair.first()?.clone();
    let c = &scene.camera;
    let view = c.target - c.eye;
    let distance = view.length().max(1e-6);
    let forward = view / distance;
    let right = forward.cross(c.up).normalize_or(Vec3::X);
    let mut out = scene.clone();
    out.hair = (0..n)
        .map(|i| {
            let depth = 0.5 * distance * i as f32;
            let side = [0.0, -1.0, 1.0][i as usize % 3];
            let mut h = first.clone();
            h.transform.translate += forward * depth + right * side * 0.3 * (distance + depth);
            h
        })
        .collect();
    // The far plane reaches the last one.
    let reach = distance + 0.5 * distance * n.saturating_sub(1) as f32;
    out.camera.far = out.camera.far.max(reach * 1.5);
    Some(out)
}

/// How many characters each series fits in the time the `strands` series needs for two: the
/// largest point whose frame time is at most that (`None` where the reference is missing).
pub(crate) fn budget_counts(rows: &[Row], series: &[&'static str]) -> Option<Vec<(String, f64)>> {
    let time = |t: &str, x: f64| {
        rows.iter()
            .find(|r| r.technique == t && r.x == x)
            .and_then(|r| r.result.as_ref().ok())
            .map(|m| m.frame_ms)
    };
    let budget = time("strands", 2.0)?;
    Some(
        series
            .iter()
            .map(|&t| {
                let fits = rows
                    .iter()
                    .filter(|r| r.technique == t)
                    .filter(|r| r.result.as_ref().is_ok_and(|m| m.frame_ms <= budget))
                    .map(|r| r.x)
                    .fold(0.0, f64::max);
                (t.to_string(), fits)
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn copies_recede_in_depth_and_stay_in_view() {
        let scene = tress_render::session::scene_from_inputs(&[]).unwrap().0;
        let c = crowd(&scene, 16).unwrap();
        assert_eq!(c.hair.len(), 16);
        assert_eq!(c.hair[0], scene.hair[0], "the first is the scene's own");
        let eye = scene.camera.eye;
        let forward = (scene.camera.target - eye).normalize();
        let aspect = scene.output.aspect();
        let tan_y = (scene.camera.fov_y_deg.to_radians() * 0.5).tan();
        let mut last = f32::NEG_INFINITY;
        for h in &c.hair {
            let p = scene.camera.target + h.transform.translate - scene.hair[0].transform.translate;
            let depth = (p - eye).dot(forward);
            assert!(depth > last, "each farther than the one before");
            last = depth;
            let lateral = (p - eye - forward * depth).length();
            assert!(
                lateral < depth * tan_y * aspect,
                "in view: {lateral} at {depth}"
            );
        }
        assert!(c.camera.far > last, "the far plane reaches the last");
        assert!(c.validate().is_ok());
        assert!(crowd(&Scene::default(), 3).is_none(), "no hair, no crowd");
    }

    #[test]
    fn the_budget_is_the_strands_time_for_two() {
        let row = |t, x, frame_ms| Row {
            technique: t,
            x,
            result: Ok(super::super::measure::Measurement {
                frame_ms,
                timing: super::super::measure::TimingSource::Gpu,
                wall_ms: frame_ms,
                passes: Vec::new(),
                coverage_pct: 1.0,
                memory: Default::default(),
                frames: 1,
                oit: None,
                flip: None,
            }),
        };
        let rows = [
            row("strands", 1.0, 10.0),
            row("strands", 2.0, 20.0),
            row("strands", 4.0, 40.0),
            row("auto", 1.0, 6.0),
            row("auto", 2.0, 9.0),
            row("auto", 4.0, 15.0),
            row("auto", 8.0, 26.0),
        ];
        let counts = budget_counts(&rows, &["strands", "auto"]).unwrap();
        assert_eq!(counts, [("strands".into(), 2.0), ("auto".into(), 4.0)]);
        assert!(budget_counts(&rows[2..], &["auto"]).is_none());
    }
}
