//! Trace a scene file without the `tress` CLI (which also builds the GPU renderer):
//! `cargo run --release -p tress-trace --example trace_scene -- SCENE.toml OUT.png [trace.NAME=VALUE | KEY=VALUE]...`
//!
//! Arguments after the output are tracer settings (`trace.spp=16`) or scene overrides
//! (`output.width=256`). Prints the BVH build time, the render time and rays per second.

use std::process::ExitCode;

use tress_scene::Scene;
use tress_trace::{SceneGeometry, TraceError, TraceSettings, Tracer};

fn run() -> Result<(), TraceError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene_path, out, sets @ ..] = args.as_slice() else {
        return Err(TraceError::Invalid(
            "usage: trace_scene SCENE.toml OUT.(png|exr) [trace.NAME=VALUE | KEY=VALUE]...".into(),
        ));
    };
    let mut scene = Scene::from_path(scene_path)?;
    let mut settings = TraceSettings::default();
    for set in sets {
        match set.strip_prefix("trace.").and_then(|s| s.split_once('=')) {
            Some((name, value)) => settings.set(name, value)?,
            None => scene.apply_override(set)?,
        }
    }
    let geometry = SceneGeometry::load(&scene)?;
    let tracer = Tracer::new(&scene, &geometry, &settings)?;
    let rendered = tracer.render(&|_| {});
    rendered.image.save(out)?;
    let s = rendered.stats;
    println!(
        "{} segments ({} BVH references), {} triangles ({} width); BVH {:.2} s; {}x{} at {} spp: {} rays in {:.2} s, {:.3} M rays/s",
        tracer.segment_count(),
        tracer.reference_count(),
        tracer.triangle_count(),
        tracer.strand_width().name(),
        tracer.build_seconds(),
        scene.output.width,
        scene.output.height,
        settings.spp,
        s.rays,
        s.seconds,
        s.rays_per_second() / 1e6
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("trace_scene: {e}");
            ExitCode::from(2)
        }
    }
}
