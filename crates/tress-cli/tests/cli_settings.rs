//! `tress settings`: the scene reference the book's tables come from. No GPU needed.

mod common;

use common::tress;
use tress_render::{SETTING_TABLES, settings_markdown};

#[test]
fn settings_prints_the_reference_as_toml_and_markdown() {
    let out = tress(&["settings", "strands"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.starts_with("[strands]\n") && text.contains("\nwidth_px = 1.5\n"),
        "{text}"
    );
    // What it prints is a scene a renderer reads, at the defaults.
    let scene = tress_scene::Scene::from_str(&text, ".").unwrap();
    let settings = tress_render::scene_setup::strand_settings(&scene).unwrap();
    assert_eq!(settings, tress_render::StrandSettings::default());

    let out = tress(&["settings", "--markdown"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let all: Vec<String> = SETTING_TABLES
        .iter()
        .map(|t| settings_markdown(t).unwrap())
        .collect();
    assert_eq!(String::from_utf8(out.stdout).unwrap(), all.join("\n"));

    let out = tress(&["settings", "camera"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("camera") && err.contains("strands"), "{err}");
}
