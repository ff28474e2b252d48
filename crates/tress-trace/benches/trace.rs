//! Reference tracer speed on the generated ponytail (Jansson et al. 2019, Table 1: 136,320
//! strands) at 10% of its strands, the built-in demo's density: BVH build, and a small render
//! with shadows and AO. Run with `cargo bench -p tress-trace --bench trace`.
//!
//! The full-size figures (rays per second at 136,320 strands, time to a converged 512×512
//! image) come from `tress reference --json`; see the crate's README section in the project
//! README.

use divan::{Bencher, black_box};
use tress_scene::Scene;
use tress_trace::{SceneGeometry, TraceSettings, Tracer};

fn main() {
    divan::main();
}

/// The demo camera and lights with the ponytail at `ratio` of its strands, `size` pixels.
fn scene(ratio: f32, size: u32) -> Scene {
    let text = format!(
        "[camera]\neye = [58.0, 2.0, -56.0]\ntarget = [0.0, -8.0, -5.0]\nfov_y_deg = 35.0\n\
         [[light]]\ndirection = [0.5, 0.8, -0.4]\n\
         [[hair]]\ngenerator = {{ style = \"ponytail\", seed = 1 }}\nstrand_ratio = {ratio}\n\
         [output]\nwidth = {size}\nheight = {size}\n"
    );
    Scene::from_str(&text, ".").expect("bench scene")
}

#[divan::bench(sample_count = 5)]
fn build_bvh_ponytail_10pct(bencher: Bencher<'_, '_>) {
    let sc = scene(0.1, 64);
    let geometry = SceneGeometry::load(&sc).expect("ponytail");
    bencher.bench(|| {
        Tracer::new(&sc, black_box(&geometry), &TraceSettings::default()).expect("tracer")
    });
}

#[divan::bench(sample_count = 5)]
fn render_ponytail_10pct_64px_4spp(bencher: Bencher<'_, '_>) {
    let sc = scene(0.1, 64);
    let geometry = SceneGeometry::load(&sc).expect("ponytail");
    let settings = TraceSettings {
        spp: 4,
        ..TraceSettings::default()
    };
    let tracer = Tracer::new(&sc, &geometry, &settings).expect("tracer");
    bencher.bench(|| tracer.render(&|_| {}));
}

/// The paper's scale: all 136,320 strands, 128×128 at 1 sample a pixel (the BVH's traversal on
/// a full-size asset; which split rule the BVH keeps was measured here and on the AO bake).
#[divan::bench(sample_count = 3)]
fn render_ponytail_full_128px_1spp(bencher: Bencher<'_, '_>) {
    let sc = scene(1.0, 128);
    let geometry = SceneGeometry::load(&sc).expect("ponytail");
    let settings = TraceSettings {
        spp: 1,
        ..TraceSettings::default()
    };
    let tracer = Tracer::new(&sc, &geometry, &settings).expect("tracer");
    bencher.bench(|| tracer.render(&|_| {}));
}
