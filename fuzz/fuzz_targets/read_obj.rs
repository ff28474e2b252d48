//! Fuzz the OBJ readers: hair cards (`PatchMesh::from_obj`) and head meshes
//! (`TriMesh::from_obj`). Any input must give `Ok` or `Err`; accepted cards must write back and
//! read again.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_obj_check(data)
);
