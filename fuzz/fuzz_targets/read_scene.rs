//! Fuzz the scene TOML reader: any text must give `Ok` or `Err`, never a panic; an accepted
//! scene must serialize and read back equal.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_scene::Scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(scene) = Scene::from_str(text, ".") {
        let _ = scene.technique_settings::<toml::Table>("strands");
        if let Ok(written) = scene.to_toml_string() {
            let again = Scene::from_str(&written, ".").expect("a written scene reads back");
            assert_eq!(again, scene);
        }
    }
});
