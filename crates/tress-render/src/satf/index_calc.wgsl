// Index calculation (Table 1, "I"; Xu et al. 2006 §6.2.1): per boundary sector, Params(b) =
// (rho_feature, theta_v, theta_l) with the azimuths of the eye and the key light at the sector's
// anchor and the nearest database sample (`cs_sectors`); per HSV, the uniformity test of
// equation 6 and the records to use: the averaged Params_ave's when uniform, else the two
// boundary sectors' (`cs_hsvs`). Owner: `IndexCalc`.

#include "common/camera.wgsl"
#include "common/lights.wgsl"
#include "satf/types.wgsl"
#include "satf/online.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> lights: Lights;
@group(0) @binding(2) var<uniform> params: SatfParams;
@group(0) @binding(3) var<storage, read> sectors: array<SatfSector>;
// Database features, one per sample (w unused).
@group(0) @binding(4) var<storage, read> db_features: array<vec4f>;
@group(0) @binding(5) var<storage, read_write> sector_params: array<SectorParams>;
@group(0) @binding(6) var<storage, read_write> hsvs: array<HsvRecord>;
@group(0) @binding(7) var<storage, read_write> counters: SatfCounters;

// Database::nearest_sample: the sample of least weighted squared feature distance (the first of
// equals).
fn nearest_sample(f: vec3f) -> u32 {
    var best = 0u;
    var best_d = 3.4e38;
    let w = params.feature_weights;
    for (var i = 0u; i < params.sample_count; i = i + 1u) {
        let d = db_features[i].xyz - f;
        let dist = w.x * d.x * d.x + w.y * d.y * d.y + w.z * d.z * d.z;
        if dist < best_d {
            best = i;
            best_d = dist;
        }
    }
    return best;
}

@compute @workgroup_size(64)
fn cs_sectors(@builtin(global_invocation_id) id: vec3u) {
    let g = id.x;
    if g >= params.sector_count {
        return;
    }
    let s = sectors[g];
    let to_eye = camera_to_eye(camera, s.position);
    var theta_l = 0.0;
    if params.key_light < min(lights.count, MAX_LIGHTS) {
        theta_l = satf_azimuth(lights.lights[params.key_light].to_light, s.normal, s.s_axis);
    }
    var out: SectorParams;
    out.features = s.features;
    out.theta_v = satf_azimuth(to_eye, s.normal, s.s_axis);
    out.theta_l = theta_l;
    out.sample = nearest_sample(s.features);
    sector_params[g] = out;
}

fn hsv_params(s: SectorParams) -> HsvParams {
    return HsvParams(s.features, s.theta_v, s.theta_l);
}

@compute @workgroup_size(64)
fn cs_hsvs(@builtin(global_invocation_id) id: vec3u) {
    let h = id.x;
    if h >= params.hsv_count {
        return;
    }
    // HSV (i, layer, m) of a cluster lies between sectors (i, layer, m) and (i + 1, layer, m)
    // (ShellSampling::hsv_sectors).
    let per_layer_ring = params.layers * params.su;
    let hsvs_per_cluster = params.st * per_layer_ring;
    let cluster = h / hsvs_per_cluster;
    let local = h % hsvs_per_cluster;
    let top = cluster * (params.st + 1u) * per_layer_ring + local;
    let bottom = top + per_layer_ring;
    let a = sector_params[top];
    let b = sector_params[bottom];
    let pa = hsv_params(a);
    let pb = hsv_params(b);
    var rec: HsvRecord;
    if satf_is_uniform(pa, pb, params.feature_weights, params.angle_weight, params.k_threshold) {
        let ave = satf_average_params(pa, pb);
        rec.sample1 = nearest_sample(ave.features);
        rec.view1 = satf_angle_bin(ave.theta_v, params.view_angles);
        rec.light1 = satf_angle_bin(ave.theta_l, params.light_angles);
        rec.sample2 = rec.sample1;
        rec.view2 = rec.view1;
        rec.light2 = rec.light1;
        rec.uniform = 1u;
        atomicAdd(&counters.uniform_hsvs, 1u);
    } else {
        rec.sample1 = a.sample;
        rec.view1 = satf_angle_bin(a.theta_v, params.view_angles);
        rec.light1 = satf_angle_bin(a.theta_l, params.light_angles);
        rec.sample2 = b.sample;
        rec.view2 = satf_angle_bin(b.theta_v, params.view_angles);
        rec.light2 = satf_angle_bin(b.theta_l, params.light_angles);
        rec.uniform = 0u;
        atomicAdd(&counters.interpolated_hsvs, 1u);
    }
    hsvs[h] = rec;
}
