//! The library entry point used by quality comparisons: `render_reference` of a scene, scored
//! with `metrics::compare`.

use tress_scene::Scene;
use tress_trace::{DisplayImage, TraceSettings, metrics, render_reference};

fn scene(extra: &str) -> Scene {
    let text = format!(
        "[[hair]]\ngenerator = {{ style = \"curly\", strands = 200, vertices = 24, thickness = 0.1 }}\n\
         [output]\nwidth = 40\nheight = 30\n{extra}"
    );
    Scene::from_str(&text, ".").unwrap()
}

#[test]
fn reference_renders_the_scene_size_deterministically_and_scores_against_itself() {
    let settings = TraceSettings {
        spp: 2,
        ..TraceSettings::default()
    };
    let a = render_reference(&scene(""), &settings).unwrap();
    assert_eq!((a.width, a.height, a.pixels.len()), (40, 30, 1200));
    assert!(
        a.pixels
            .iter()
            .all(|p| p.is_finite() && p.min_element() >= 0.0)
    );
    let b = render_reference(&scene(""), &settings).unwrap();
    assert_eq!(a, b);

    let da = DisplayImage::from_linear(&a);
    let same = metrics::compare(&da, &da).unwrap().scores;
    assert_eq!((same.flip, same.rmse, same.ssim), (0.0, 0.0, 1.0));

    // A different view of the same hair scores worse than the same view.
    let moved = render_reference(&scene("[camera]\nfov_y_deg = 20.0\n"), &settings).unwrap();
    let other = metrics::compare(&da, &DisplayImage::from_linear(&moved))
        .unwrap()
        .scores;
    assert!(
        other.flip > 0.01 && other.rmse > 0.01 && other.ssim < 0.99,
        "{other:?}"
    );
}

#[test]
fn bad_scene_values_are_errors_not_panics() {
    let settings = TraceSettings::default();
    let e = render_reference(&scene("[strands]\nwidth_px = -1.0\n"), &settings)
        .unwrap_err()
        .to_string();
    assert!(e.contains("strands.width_px"), "{e}");
    let bad = TraceSettings { spp: 0, ..settings };
    assert!(render_reference(&scene(""), &bad).is_err());
    let missing = Scene::from_str("[[hair]]\nfiles = [\"missing.hair\"]\n", ".").unwrap();
    let e = render_reference(&missing, &TraceSettings::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.hair"), "{e}");
}
