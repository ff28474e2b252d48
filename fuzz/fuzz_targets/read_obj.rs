//! Fuzz the OBJ readers: hair cards (`PatchMesh::from_obj`) and head meshes
//! (`TriMesh::from_obj`). Any input must give `Ok` or `Err`; accepted cards must write back and
//! read again.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_hair::generate::TriMesh;
use tress_hair::patches::PatchMesh;

fuzz_target!(|data: &[u8]| {
    if let Ok(cards) = PatchMesh::from_obj(data) {
        let again = PatchMesh::from_obj(cards.to_obj().as_bytes()).expect("written cards re-read");
        assert_eq!(again.triangle_count(), cards.triangle_count());
    }
    let _ = TriMesh::from_obj(data);
});
