//! What each fuzz target checks, one function a target: the fuzz targets call these, and the
//! workspace's regression test (`crates/tress-cli/tests/fuzz_regressions.rs`) feeds every
//! committed seed and regression input to the same functions, so CI replays what the fuzzer
//! found without running it.
//!
//! A check fails by panicking: a reader that panics on an input, or a file it accepted that
//! does not survive being written and read back.

use tress_hair::formats::{
    ReadOptions, parse_tfx, read_abc, read_data, read_hair, read_tfx, read_usd_bytes, write_data,
    write_hair, write_tfx,
};

/// What a target runs on one input; it panics when a check fails.
pub type Check = fn(&[u8]);

/// Every target: its name (its `fuzz_targets/NAME.rs`, `seeds/NAME/` and `regressions/NAME/`)
/// and its check.
pub const TARGETS: &[(&str, Check)] = &[
    ("read_abc", read_abc_check),
    ("read_ct2hair", read_ct2hair_check),
    ("read_data", read_data_check),
    ("read_gltf", read_gltf_check),
    ("read_hair", read_hair_check),
    ("read_obj", read_obj_check),
    ("read_satfdb", read_satfdb_check),
    ("read_scene", read_scene_check),
    ("read_tfx", read_tfx_check),
    ("read_usd", read_usd_check),
];

/// Alembic Ogawa curves: `tress_alembic::read`, then tress's curves at a frame the input's
/// length picks (an animated cache's later samples; a still file's one).
pub fn read_abc_check(data: &[u8]) {
    let _ = tress_alembic::read(data);
    let options = ReadOptions {
        cubic_segments: 2,
        frame: data.len() as u32 % 3,
    };
    let _ = read_abc(data, &options);
}

/// CT2Hair `.bin`.
pub fn read_ct2hair_check(data: &[u8]) {
    let _ = tress_hair::formats::read_ct2hair(data);
}

/// USC-HairSalon `.data`, then a write/read round trip of what it accepts.
pub fn read_data_check(data: &[u8]) {
    if let Ok((asset, _)) = read_data(data) {
        let bytes = write_data(&asset).expect("an asset read from .data can be written");
        assert_eq!(read_data(&bytes).expect("re-read").0, asset);
    }
}

/// glTF / GLB meshes (buffers from the file only).
pub fn read_gltf_check(data: &[u8]) {
    let _ = tress_hair::formats::gltf::read_gltf(data, None);
}

/// Cem Yuksel `.hair` (and the vkhr extension), then a write/read round trip.
pub fn read_hair_check(data: &[u8]) {
    if let Ok(asset) = read_hair(data) {
        let bytes = write_hair(&asset).expect("an asset read from .hair can be written as .hair");
        assert_eq!(read_hair(&bytes).expect("re-read"), asset);
    }
}

/// OBJ hair cards (then a card round trip) and OBJ head meshes.
pub fn read_obj_check(data: &[u8]) {
    use tress_hair::generate::TriMesh;
    use tress_hair::patches::PatchMesh;
    if let Ok(cards) = PatchMesh::from_obj(data) {
        let again = PatchMesh::from_obj(cards.to_obj().as_bytes()).expect("written cards re-read");
        assert_eq!(again.triangle_count(), cards.triangle_count());
    }
    let _ = TriMesh::from_obj(data);
}

/// The SATF database (`.satfdb`), as it is and with its trailing checksum fixed up so the body
/// is explored.
pub fn read_satfdb_check(data: &[u8]) {
    use tress_satf::database::Database;
    let _ = Database::from_bytes(data);
    if data.len() >= 8 {
        let mut fixed = data.to_vec();
        let body = fixed.len() - 8;
        let sum = tress_satf::format::fnv1a64(&fixed[..body]);
        fixed[body..].copy_from_slice(&sum.to_le_bytes());
        let _ = Database::from_bytes(&fixed);
    }
}

/// Scene TOML (and its technique settings), then writing the scene back and reading it again.
pub fn read_scene_check(data: &[u8]) {
    use tress_scene::Scene;
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(scene) = Scene::from_str(text, ".") {
        let _ = scene.technique_settings::<toml::Table>("strands");
        if let Ok(written) = scene.to_toml_string() {
            let again = Scene::from_str(&written, ".").expect("a written scene reads back");
            assert_eq!(again, scene);
        }
    }
}

/// TressFX `.tfx` as it is and with its version field set to 3.0 and 4.0, each followed by a
/// 4.x write/read round trip of the guides.
pub fn read_tfx_check(data: &[u8]) {
    fn check(data: &[u8]) {
        let _ = read_tfx(data);
        if let Ok(file) = parse_tfx(data) {
            let bytes = write_tfx(&file.guides).expect("guides of a .tfx file have equal strands");
            assert_eq!(read_tfx(&bytes).expect("re-read"), file.guides);
        }
    }
    check(data);
    if data.len() >= 4 {
        for version in [3.0f32, 4.0] {
            let mut with_version = data.to_vec();
            with_version[..4].copy_from_slice(&version.to_le_bytes());
            check(&with_version);
        }
    }
}

/// The USD flavour an input of `read_usd` is read as: its first byte picks it.
pub fn usd_flavour(data: &[u8]) -> Option<(&'static str, &[u8])> {
    let (&pick, file) = data.split_first()?;
    Some((["usda", "usdc", "usdz"][usize::from(pick % 3)], file))
}

/// USD (`.usda`, `.usdc`, `.usdz` through openusd, then tress's curves and meshes); the first
/// byte picks the flavour ([`usd_flavour`]), the rest is the file.
pub fn read_usd_check(data: &[u8]) {
    if let Some((ext, file)) = usd_flavour(data) {
        let options = ReadOptions {
            cubic_segments: 2,
            frame: data.len() as u32 % 3,
        };
        let _ = read_usd_bytes(file, ext, &options);
    }
}

/// For a fuzz target's `init`: make every panic abort the process, including one tress catches
/// and silences inside a third-party reader (`tress_hair::panic_guard`), so the fuzzer sees it.
pub fn abort_on_every_panic() {
    tress_hair::panic_guard::install();
    let silenced = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        silenced(info);
        std::process::abort();
    }));
}
