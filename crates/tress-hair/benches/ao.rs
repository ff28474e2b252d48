//! Ambient-occlusion bake speed for the default generated patch head
//! ([`PatchParams::default`], baked against the head mesh with [`AoParams::default`]: 64 rays
//! per hemisphere, both hemispheres). Run with `cargo bench -p tress-hair --bench ao`.
//!
//! Also measured: building the head and the patches (what the bake is run after) and the
//! inside-to-outside sort.

use divan::{Bencher, black_box};
use tress_hair::generate::{Head, TriMesh};
use tress_hair::patches::{
    AoParams, PatchMesh, PatchParams, bake_ao, generate_patches, sorted_indices,
};

fn main() {
    divan::main();
}

/// Head mesh resolution used with the patches (as `tress` draws the head).
const HEAD_SUBDIVISIONS: u32 = 48;

fn scene() -> (PatchMesh, TriMesh) {
    let params = PatchParams::default();
    let mesh = generate_patches(&params).expect("valid defaults");
    (mesh, params.head.mesh(HEAD_SUBDIVISIONS))
}

#[divan::bench(sample_count = 5)]
fn bake_default_patch_head(bencher: Bencher<'_, '_>) {
    let (mesh, head) = scene();
    bencher
        .with_inputs(|| mesh.clone())
        .bench_local_refs(|m| bake_ao(m, Some(&head), &AoParams::default()).expect("valid"));
}

#[divan::bench(sample_count = 10)]
fn generate_default_patch_head() -> PatchMesh {
    generate_patches(black_box(&PatchParams::default())).expect("valid defaults")
}

#[divan::bench(sample_count = 20)]
fn sort_default_patch_head(bencher: Bencher<'_, '_>) {
    let (mesh, _) = scene();
    bencher.bench(|| sorted_indices(black_box(&mesh), Head::default().center));
}
