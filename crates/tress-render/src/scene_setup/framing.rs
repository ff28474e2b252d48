//! Framing a camera on hair whose scene gives none: the three-quarter view across the box's
//! largest extents, the distance at which every corner fits, and the world-unit defaults fitted
//! to the asset's unit.

use glam::Vec3;
use tress_scene::Scene;

use crate::{HybridSettings, StrandSettings, VolumeSettings};

/// The front three-quarter view direction (from the target toward the eye) of hair framed by
/// [`frame_bounds`].
pub const FRONT_VIEW: Vec3 = Vec3::new(0.45, 0.2, 1.0);

/// The side three-quarter view, taken when the hair is much thinner across `x` than along `z`.
pub const SIDE_VIEW: Vec3 = Vec3::new(1.0, 0.2, 0.45);

/// The area of a box of `extent` seen along the unit `dir` (orthographic): the sum of its faces'
/// areas weighted by how squarely each faces `dir`.
pub fn projected_area(extent: Vec3, dir: Vec3) -> f32 {
    let e = extent.abs();
    dir.x.abs() * e.y * e.z + dir.y.abs() * e.x * e.z + dir.z.abs() * e.x * e.y
}

/// The view direction [`frame_bounds`] takes for a box of `extent`: the front three-quarter
/// view, or the side one where the box shows at least 1.2 times the area from there (a mohawk,
/// a crest of fur: hair much thinner across than along, which the front view shows as a strip).
pub fn framing_direction(extent: Vec3) -> Vec3 {
    let (front, side) = (FRONT_VIEW.normalize(), SIDE_VIEW.normalize());
    if projected_area(extent, side) > 1.2 * projected_area(extent, front) {
        side
    } else {
        front
    }
}

/// The hair's unit against the centimetre-like units every world-unit default assumes: the
/// power of ten nearest `diagonal / 50` of the bounds (a head of hair spans about 50 cm), so 1
/// for an asset in centimetres, 0.01 in metres, 10 in millimetres.
pub fn unit_scale(min: Vec3, max: Vec3) -> f32 {
    let diagonal = (max - min).length();
    if !(diagonal.is_finite() && diagonal > 0.0) {
        return 1.0;
    }
    10f32.powi((diagonal / 50.0).log10().round().clamp(-6.0, 6.0) as i32)
}

/// The technique settings given in world units, with their defaults and the power of the unit
/// they scale with (`shadow_r` counts strands per unit length).
fn world_unit_defaults() -> [(&'static str, f32, i32); 7] {
    let strands = StrandSettings::default();
    let volume = VolumeSettings::default();
    let hybrid = HybridSettings::default();
    [
        ("strands.shadow_r", strands.shadow_r, -1),
        ("strands.shadow_bias", strands.shadow_bias, 1),
        ("volume.strand_width", volume.strand_width, 1),
        ("volume.ao_radius", volume.ao_radius, 1),
        ("hybrid.near", hybrid.near, 1),
        ("hybrid.far", hybrid.far, 1),
        (
            "satf.shadow_bias",
            crate::satf::SatfSettings::default().shadow_bias,
            1,
        ),
    ]
}

/// Give every world-unit setting the scene leaves at its default its default times `scale` (to
/// its power): the depth bias, shadow density, AO radius and LOD distances of an asset in metres
/// are those of the same asset in centimetres. The settings are `strands.shadow_r` (per unit
/// length, so divided by `scale`), `strands.shadow_bias`, `volume.strand_width`,
/// `volume.ao_radius`, `hybrid.near`, `hybrid.far` and `satf.shadow_bias`.
pub fn scale_world_defaults(scene: &mut Scene, scale: f32) {
    if scale == 1.0 {
        return;
    }
    for (key, default, power) in world_unit_defaults() {
        let (table, name) = key.split_once('.').unwrap_or((key, key));
        let given = scene
            .technique_table(table)
            .is_some_and(|t| t.contains_key(name));
        if !given {
            let value = f64::from(default) * f64::from(scale).powi(power);
            // A number the TOML parser reads back: the override cannot fail.
            let _ = scene.apply_override(&format!("{key}={value:e}"));
        }
    }
}

/// A camera framing `bounds` (min, max) from a three-quarter view across the box's largest
/// extents ([`framing_direction`]), with the near and far planes around it, and the world-unit
/// defaults fitted to the asset's unit ([`unit_scale`], [`scale_world_defaults`]): what
/// `tress render hair-file` uses when no scene gives a camera. Settings loaded before the call
/// are reloaded with [`PreparedScene::reload_settings`](super::PreparedScene::reload_settings).
pub fn frame_bounds(scene: &mut Scene, min: Vec3, max: Vec3) {
    scale_world_defaults(scene, unit_scale(min, max));
    let center = (min + max) * 0.5;
    let radius = ((max - min).length() * 0.5).max(1e-3);
    let dir = framing_direction(max - min);
    // The nearest distance at which every corner of the box projects inside the frame with a
    // 5% margin on both axes (a bounding sphere would leave a tall, thin asset small in a
    // portrait frame): a corner at `r` from the centre lies `d - r·dir` deep and must have
    // `|r·axis| · 1.05 <= depth · tan(half fov)` on each screen axis.
    let tan_y = (scene.camera.fov_y_deg.to_radians() * 0.5).tan();
    let tan_x = tan_y * scene.output.aspect();
    let right = Vec3::Y.cross(dir).normalize_or(Vec3::X);
    let up = dir.cross(right);
    let mut distance = radius * 1e-2;
    for i in 0..8 {
        let corner = Vec3::select(
            glam::BVec3::new(i & 1 == 0, i & 2 == 0, i & 4 == 0),
            min,
            max,
        );
        let r = corner - center;
        let fit = (r.dot(right).abs() / tan_x).max(r.dot(up).abs() / tan_y) * 1.05;
        distance = distance.max(r.dot(dir) + fit);
    }
    scene.camera.eye = center + dir * distance;
    scene.camera.target = center;
    scene.camera.up = Vec3::Y;
    scene.camera.near = (distance - radius * 1.5).max(distance * 1e-3);
    scene.camera.far = distance + radius * 1.5;
}
