//! Reference CPU ray tracer for tress scenes, and image-quality metrics.
//!
//! The hybrid hair paper (Jansson et al. 2019) compares its volume ambient occlusion with a
//! ray-traced ground truth (§3.4, Figure 5). This crate renders that ground truth for any scene
//! file: the same hair, head, camera, lights and material the GPU techniques draw, shaded with
//! the same `tress-shading` formulas, but with every strand intersected as geometry, shadows and
//! ambient occlusion traced through the translucent strands, and many samples per pixel. The
//! [`metrics`] module scores a technique's image against it (mean FLIP, RMSE, SSIM).
//!
//! ```
//! use tress_scene::Scene;
//! use tress_trace::{DisplayImage, TraceSettings, metrics, render_reference};
//! # fn main() -> Result<(), tress_trace::TraceError> {
//! // A scene (`Scene::from_path("scenes/demo.toml")` reads a file): 200 strands, 48 × 32 pixels.
//! let text = r#"
//!     output = { width = 48, height = 32 }
//!     [[hair]]
//!     generator = { style = "straight", strands = 200, vertices = 8 }
//! "#;
//! let scene = Scene::from_str(text, ".")?;
//! let settings = TraceSettings { spp: 4, ..Default::default() };
//! let image = render_reference(&scene, &settings)?; // linear RGB; `image.save("ref.png")`
//! assert_eq!((image.width, image.height), (48, 32));
//!
//! // Score a technique's image (`DisplayImage::read("strands.png")`; here the same render)
//! // against the reference: mean FLIP, RMSE and SSIM.
//! let reference = DisplayImage::from_linear(&image);
//! let scores = metrics::compare(&reference, &reference)?.scores;
//! assert_eq!((scores.flip, scores.rmse, scores.ssim), (0.0, 0.0, 1.0));
//! # Ok(()) }
//! ```
//!
//! # Implementation
//!
//! - **Scene (as the GPU path reads it).** All `[[hair]]` entries merged; the head from
//!   [`tress_scene::Scene::head_source`] (the generated ellipsoid meshed at 64 subdivisions, or
//!   an OBJ through `TriMesh::read_obj`); directional lights with `l` = the scene's direction
//!   towards the light and radiance `color · intensity`; the first hair entry's material; the
//!   `[strands]` table's `alpha`, `width_px`, `shading` and `thickness_fade`, with the
//!   rasterizer's defaults (0.6, 1.5 px, Kajiya-Kay, tip). The camera is a pinhole with the
//!   scene's eye, target, up, vertical field of view and output size, clipped to its near and
//!   far planes; pixel `(x, y)` covers the same film area as the GPU's pixel.
//!   [`Tracer::with_camera`] takes any view and projection matrix pair instead ([`ViewCamera`],
//!   the GPU's convention: off-centre, skewed and orthographic projections included); its rays
//!   run from the unprojected NDC point at clip depth 0 to the one at depth 1.
//! - **Strands** are chains of capsules ([`geometry`]): each segment is a cylinder with
//!   half-sphere caps, its radius interpolated along the segment; caps count only at the root
//!   and the tip, so a ray through a joint crosses a translucent strand once. Their width
//!   ([`StrandWidth`]): by default (`auto`) the physical thickness, the material's `thickness`
//!   or else the asset's per-vertex thickness (Jansson §3: strands of constant radius; the
//!   generators taper to a tenth at the tip); an asset without thickness is drawn like the GPU
//!   rasterizer draws it (`screen`): a width in pixels converted to world units at each vertex's
//!   distance from the camera (`2 · tan(fov_y / 2) · depth / height` per pixel). The default
//!   screen width is half the GPU's `strands.width_px`: the rasterizer's ribbon is `width_px`
//!   wide but its §3.2 coverage falls linearly from 1 at the centre to 0 at the edges, so it puts
//!   down the ink of a solid line half as wide. In screen mode the GPU's `thickness_fade` scales
//!   alpha as on the GPU (tip: thickness over the asset's thickest vertex; projected: the
//!   projected thickness over `width_px`); in thickness mode the geometry itself tapers.
//! - **Opacity.** A strand's alpha is `strands.alpha · (1 - transparency)` (per vertex,
//!   interpolated), the rasterizer's strand alpha. Camera rays use *stochastic transparency*:
//!   every strand the ray enters stops it with probability alpha, decided by a hash of the
//!   camera sample and the primitive, inside one nearest-hit traversal; the expected result is
//!   exactly front-to-back compositing, `Σ_k α_k Π_{j<k} (1 - α_j) c_k`, and it converges with
//!   the pixel's samples. The head is opaque.
//! - **Shadows** (§3.4's ground truth for ADSM). One ray per light from the hit (on the strand's
//!   axis, skipping the hit segment and its two neighbours on the strand; or just off a head
//!   triangle) towards the light: its transmittance is `Π (1 - α)` over every strand it enters,
//!   exactly the `(1 - α)^n` that ADSM estimates with `n = d · r` and the volume counts with its
//!   density, and 0 if it meets the head. Once the product falls below 0.25 the ray plays
//!   Russian roulette (survive with probability `product / 0.25`, carrying 0.25): unbiased, and
//!   a ray inside dense hair stops after a few strands instead of traversing on until the
//!   product is negligible (2.4 times faster shadow rays on the full ponytail). AO rays do the
//!   same.
//! - **Ambient occlusion** (§3.4, Figure 5). `ao_samples` cosine-weighted directions per camera
//!   sample in the hemisphere around the surface normal, each contributing its transmittance
//!   (translucent strands occlude by their alpha) up to `ao_radius`; their mean is the AO.
//!   Strands have no surface normal: they use the rasterizer's Scheuermann normal (the direction
//!   from the centre of the hair's bounds, perpendicular to the tangent), so the hemisphere faces
//!   out of the hair volume: strands on the outside see the sky, strands inside or against the
//!   head do not. The head uses its geometric normal facing the viewer. A point on an open plane
//!   gets AO 1 and a point inside a closed box 0 (tested).
//! - **Physically based shading** (`strands.shading = "marschner"`, or `patches.shading =
//!   "marschner"` with the patches technique): a path tracer instead of the direct shading below
//!   (`src/tracer/path.rs`): opaque fibres with Chiang et al. 2016's BSDF ([`chiang`]) and the
//!   material's fibre ([`tress_scene::Material::fiber`]), a Lambertian head, next-event
//!   estimation of the directional lights (irradiance `π · color · intensity`), a uniform sky of
//!   radiance `ambient` for rays that leave after a bounce, up to `bounces` bounces with Russian
//!   roulette; its secondary rays start at the hit point on the fibre's surface. Checked
//!   against Mitsuba 3 (`docs/mitsuba/compare.py`, and `tests/cli_mitsuba.rs` of `tress-cli`
//!   against its committed images). The AO and shadow AOVs are those of the direct tracer
//!   below, with opaque strands.
//! - **Shading** uses the `tress-shading` twins of the GPU's WGSL with the rasterizer's inputs:
//!   Kajiya-Kay ([`tress_shading::kajiya_kay()`]) with the base color as `K_d` and the primary
//!   highlight as `K_s`, `p`; or Scheuermann's [`tress_shading::hair_lighting`] with the
//!   rasterizer's per-strand random shift and noise (the same hash, [`sampling::strand_random`]).
//!   Per light the term is multiplied by the traced visibility; the ambient term `ambient · base`
//!   by the AO (the GPU rasterizer has no AO: its ambient is unoccluded). The head is Lambert
//!   (`head_color · (ambient · AO + Σ radiance · max(n·l, 0) · visibility)`) with two-sided
//!   interpolated normals, like the GPU's head pass.
//! - **Sampling.** `spp` camera samples per pixel on a jittered rank-1 (Fibonacci) lattice, which
//!   is stratified along both image axes (thin strands are lines, so 1D stratification across
//!   them is what reduces their aliasing), box-filtered. AO directions are stratified over the
//!   pixel's samples the same way. Random numbers come from one SplitMix64 stream per pixel
//!   seeded by `seed` and the pixel index, so images are deterministic whatever the thread
//!   count. Rows are rendered in parallel with rayon.
//! - **BVH** ([`bvh`]): one binned-SAH hierarchy over segments and triangles. A thin diagonal
//!   segment fills little of its box, so rays through hair would test many segments they miss:
//!   long segments are referenced in up to 4 pieces (at most 1/128 of the hair's diagonal
//!   long), each bounding its part of the capsule and reporting only hits in its part. On the
//!   demo ponytail this made shadow and AO rays about 4 times faster.
//! - **AOVs** ([`Aov`]): the color, the AO, or the light visibility (luminance-weighted over the
//!   lights) of the surface each sample stops at, averaged like the color; the background is
//!   1 in the AO and shadow images.

//!
//! # Performance
//!
//! Measured on the project's development machine: 2 CPU cores shared with other builds (load
//! average 4 to 6 during the runs, so wall-clock figures vary by up to 2x), release build.
//!
//! - **Ponytail scale** (`scenes/ponytail.toml`: the generated ponytail at the paper's 136,320
//!   strands, 1,635,840 segments, on the 16,128-triangle head): BVH over 6.56 M references built
//!   in 11.5 to 13.3 s, 1.5 GB resident. 512×512 renders traced **96,000 to 207,000 rays per
//!   second** (median of seven runs 136,000), about 1.5 rays per camera sample (background
//!   samples trace one ray; hair and head samples one camera, one shadow ray per light and one
//!   AO ray).
//! - **Converged 512×512: 256 spp, 8 to 12 minutes** (100 M rays, 486 and 700 s for two runs,
//!   plus 13 s to build). Convergence was judged by rendering twice with different seeds and
//!   comparing the two (`tress compare-images`): the noise is gone when the renders differ by
//!   less than one 8-bit level RMS (RMSE < 1/255 = 0.0039) and SSIM exceeds 0.99.
//!
//!   | spp | FLIP (seed 1 vs 2) | RMSE | SSIM |
//!   | --- | --- | --- | --- |
//!   | 16 | 0.0096 | 0.0147 | 0.942 |
//!   | 64 | 0.0057 | 0.0072 | 0.979 |
//!   | 256 | 0.0036 | 0.0036 | 0.994 |
//!
//!   RMSE halves with every 4x samples, as Monte Carlo noise should. Mean FLIP is low from 16
//!   spp on because 60% of the image is background; SSIM and RMSE are the stricter tests here.
//!
//! ```text
//! tress reference scenes/ponytail.toml -o a.png --width 512 --height 512 --spp 256 --seed 1 --json
//! tress reference scenes/ponytail.toml -o b.png --width 512 --height 512 --spp 256 --seed 2
//! tress compare-images a.png b.png
//! cargo bench -p tress-trace --bench trace   # 10% ponytail: BVH 1.2 s, 64x64 at 4 spp 82 ms
//! ```

/// The BVH (shared with the patches' AO bake in `tress-hair`).
pub use tress_hair::bvh;
pub mod chiang;
pub mod converge;
mod error;
pub mod geometry;
mod image;
pub mod matched;
pub mod metrics;
pub mod sampling;
mod settings;
mod tracer;

pub use error::TraceError;
pub use image::{DisplayImage, Image, ImageKind, linear_to_srgb};
pub use settings::{Aov, SETTING_NAMES, StrandWidth, TraceSettings};
pub use tracer::{
    HEAD_COLOR, HEAD_SUBDIVISIONS, Rendered, SceneGeometry, TraceStats, Tracer, ViewCamera,
};

/// Render the reference image of `scene` with `settings`: load its geometry, build the tracer
/// and render (no progress reporting). This is what quality comparisons of the GPU techniques
/// call for their ground truth.
pub fn render_reference(
    scene: &tress_scene::Scene,
    settings: &TraceSettings,
) -> Result<Image, TraceError> {
    let geometry = SceneGeometry::load(scene)?;
    let tracer = Tracer::new(scene, &geometry, settings)?;
    Ok(tracer.render(&|_| {}).image)
}
