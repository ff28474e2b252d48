// Shared hair shading math: the WGSL twins of crates/tress-shading.
//
// Every function here has a CPU twin of the same name and arguments in tress-shading; the table in
// that crate's docs (src/lib.rs) lists both signatures side by side, and the paper references,
// conventions and the reasons for each choice live in its module docs. Pure functions only: no
// bindings, no globals. Conventions: directions point away from the shaded point (l towards the
// light, v towards the eye), t is the unit tangent from root to tip, colors are linear RGB,
// compositing inputs are straight colors and accumulators premultiplied, screen coordinates have
// their origin at the top-left with y down (as @builtin(position)).

// ---------------------------------------------------------------------------------------------
// Helpers

// sqrt(1 - c^2), clamped so |c| rounded slightly above 1 gives 0 instead of NaN.
fn sin_from_cos(c: f32) -> f32 {
    return sqrt(max(1.0 - c * c, 0.0));
}

// ---------------------------------------------------------------------------------------------
// Kajiya-Kay [KK89], Jansson et al. 2019 §3.1 (tress_shading::kajiya_kay)

struct KajiyaKay {
    diffuse: vec3f,
    specular: vec3f,
    exponent: f32,
}

// Diffuse: sin(t, l) = sqrt(1 - (t.l)^2) (KK89 §4.1).
fn kajiya_kay_diffuse(t: vec3f, l: vec3f) -> f32 {
    return sin_from_cos(dot(t, l));
}

// Specular: max(0, cos_tr cos_tv + sin_tl sin_tv)^p with cos_tr = -(t.l): the cosine between v and
// the mirror cone of the incident direction -l (KK89 §4.1). Precondition: exponent > 0.
fn kajiya_kay_specular(t: vec3f, l: vec3f, v: vec3f, exponent: f32) -> f32 {
    let cos_tl = dot(t, l);
    let cos_tv = dot(t, v);
    let cos_tr = -cos_tl;
    let cos_cone = cos_tr * cos_tv + sin_from_cos(cos_tl) * sin_from_cos(cos_tv);
    return pow(max(cos_cone, 0.0), exponent);
}

// K_d sin(t, l) + K_s spec(t, l, v, p) for one light.
fn kajiya_kay(kk: KajiyaKay, t: vec3f, l: vec3f, v: vec3f) -> vec3f {
    return kk.diffuse * kajiya_kay_diffuse(t, l)
        + kk.specular * kajiya_kay_specular(t, l, v, kk.exponent);
}

const TANGENT_SPREAD_WIDENING: f32 = 1.5;

// Kajiya-Kay for strands shaded as one with their mean tangent's direction, the mean's length
// telling their spread (Toksvig's trick on the cone lobe): p' = p / (1 + 1.5 p (1 - len)), the
// specular colour times sqrt(p' / p).
fn spread_kajiya_kay(kk: KajiyaKay, mean_length: f32) -> KajiyaKay {
    let spread = 1.0 - clamp(mean_length, 0.0, 1.0);
    let exponent = kk.exponent / (1.0 + TANGENT_SPREAD_WIDENING * kk.exponent * spread);
    return KajiyaKay(kk.diffuse, kk.specular * sqrt(exponent / kk.exponent), exponent);
}

// ---------------------------------------------------------------------------------------------
// Scheuermann 2004, "Hair Rendering and Shading" slides (tress_shading::scheuermann)

// ShiftTangent: normalize(T + shift * N). Precondition: t + shift * n != 0.
fn shift_tangent(t: vec3f, n: vec3f, shift: f32) -> vec3f {
    return normalize(t + shift * n);
}

// StrandSpecular: smoothstep(-1, 0, t.h) * sin(t, h)^exponent with h = normalize(l + v).
// Preconditions: l + v != 0, exponent > 0.
fn strand_specular(t: vec3f, v: vec3f, l: vec3f, exponent: f32) -> f32 {
    let h = normalize(l + v);
    let dot_th = dot(t, h);
    let sin_th = sin_from_cos(dot_th);
    let dir_atten = smoothstep(-1.0, 0.0, dot_th);
    return dir_atten * pow(sin_th, exponent);
}

// Softened diffuse: saturate(lerp(0.25, 1, n.l)).
fn scheuermann_diffuse(n: vec3f, l: vec3f) -> f32 {
    let n_dot_l = dot(n, l);
    return saturate(0.25 + (1.0 - 0.25) * n_dot_l);
}

// The slide's external constants (64 bytes as a uniform; mirrored in gpu/types.rs).
struct HairLighting {
    diffuse_color: vec3f,
    primary_exponent: f32,
    primary_color: vec3f,
    primary_shift: f32,
    secondary_color: vec3f,
    secondary_exponent: f32,
    secondary_shift: f32,
}

// Per-fragment inputs: tangent, normal and the values the slide reads from textures.
struct HairSample {
    tangent: vec3f,
    shift_tex: f32,
    normal: vec3f,
    spec_mask: f32,
    base_color: vec3f,
    amb_occ: f32,
}

// HairLighting: (diffuse + primary + spec_mask * secondary) * base * light_color * amb_occ.
fn hair_lighting(p: HairLighting, s: HairSample, l: vec3f, light_color: vec3f, v: vec3f) -> vec3f {
    let shift = s.shift_tex - 0.5;
    let t1 = shift_tangent(s.tangent, s.normal, p.primary_shift + shift);
    let t2 = shift_tangent(s.tangent, s.normal, p.secondary_shift + shift);
    let diffuse = scheuermann_diffuse(s.normal, l) * p.diffuse_color;
    let primary = p.primary_color * strand_specular(t1, v, l, p.primary_exponent);
    let secondary = p.secondary_color * s.spec_mask * strand_specular(t2, v, l, p.secondary_exponent);
    return (diffuse + primary + secondary) * s.base_color * light_color * s.amb_occ;
}

// ---------------------------------------------------------------------------------------------
// Strand coverage, Jansson et al. 2019 §3.2 (tress_shading::coverage)

// saturate(1 - d / (line_thickness / 2)); a line of non-positive width covers nothing.
fn coverage_from_distance(d: f32, line_thickness: f32) -> f32 {
    if line_thickness <= 0.0 {
        return 0.0;
    }
    return saturate(1.0 - d / (line_thickness * 0.5));
}

// Clip space to framebuffer pixels (top-left origin, y down). Precondition: clip.w != 0.
fn screen_from_clip(clip: vec4f, resolution: vec2f) -> vec2f {
    let ndc = clip.xy / clip.w;
    return vec2f((ndc.x + 1.0) * 0.5 * resolution.x, (1.0 - ndc.y) * 0.5 * resolution.y);
}

// The paper's strand_coverage listing (view_projection named clip_from_world), clamped to [0, 1];
// 0 for a centre point behind the eye.
fn strand_coverage(
    screen_fragment: vec2f,
    world_line: vec4f,
    clip_from_world: mat4x4f,
    resolution: vec2f,
    line_thickness: f32,
) -> f32 {
    let clip_line = clip_from_world * world_line;
    if clip_line.w <= 0.0 {
        return 0.0;
    }
    let screen_line = screen_from_clip(clip_line, resolution);
    let d = distance(screen_line, screen_fragment);
    return coverage_from_distance(d, line_thickness);
}

// saturate(thickness / line_thickness): alpha of a strand thinner than the line drawn for it.
fn tip_fade(thickness: f32, line_thickness: f32) -> f32 {
    if line_thickness <= 0.0 {
        return 0.0;
    }
    return saturate(thickness / line_thickness);
}

// ---------------------------------------------------------------------------------------------
// Approximated deep shadow maps, Jansson et al. 2019 §3.4 (tress_shading::shadow)

// Largest PCF kernel radius honoured (tress_shading::MAX_PCF_RADIUS).
const MAX_PCF_RADIUS: i32 = 8;

// (1 - alpha)^n with n < 0 as 0 and alpha clamped to [0, 1]; pow's undefined cases handled.
fn strand_visibility(n: f32, alpha: f32) -> f32 {
    let n_strands = max(n, 0.0);
    let transmittance = 1.0 - saturate(alpha);
    if n_strands <= 0.0 {
        return 1.0;
    }
    if transmittance <= 0.0 {
        return 0.0;
    }
    return pow(transmittance, n_strands);
}

// ADSM: (1 - alpha)^(d * r), d depth units past the first occluder, r strands per depth unit.
fn adsm_visibility(d: f32, r: f32, alpha: f32) -> f32 {
    return strand_visibility(d * r, alpha);
}

// d = max(0, f - s).
fn adsm_depth(fragment_depth: f32, occluder_depth: f32) -> f32 {
    return max(fragment_depth - occluder_depth, 0.0);
}

// Mean ADSM visibility over the (2k+1)^2 texels centred on `texel`, k = kernel_radius clamped to
// [0, MAX_PCF_RADIUS], equal weights, coordinates clamped to the map's edge.
fn adsm_pcf(
    map: texture_depth_2d,
    texel: vec2i,
    kernel_radius: i32,
    fragment_depth: f32,
    r: f32,
    alpha: f32,
) -> f32 {
    let k = clamp(kernel_radius, 0, MAX_PCF_RADIUS);
    let last = vec2i(textureDimensions(map, 0)) - vec2i(1);
    var sum = 0.0;
    for (var dy = -k; dy <= k; dy++) {
        for (var dx = -k; dx <= k; dx++) {
            let at = clamp(texel + vec2i(dx, dy), vec2i(0), last);
            let occluder_depth = textureLoad(map, at, 0);
            sum += adsm_visibility(adsm_depth(fragment_depth, occluder_depth), r, alpha);
        }
    }
    let side = f32(2 * k + 1);
    return sum / (side * side);
}

// ---------------------------------------------------------------------------------------------
// PPLL k-buffer compositing, Jansson et al. 2019 §3.2 (tress_shading::blend)

// acc + (1 - acc.a) * src, both premultiplied.
fn blend_under(acc: vec4f, src: vec4f) -> vec4f {
    return acc + (1.0 - acc.a) * src;
}

// One straight-color fragment behind the premultiplied accumulator (alpha clamped to [0, 1]).
fn blend_front_to_back(acc: vec4f, color: vec3f, alpha: f32) -> vec4f {
    let a = saturate(alpha);
    return blend_under(acc, vec4f(color * a, a));
}

// Order-independent tail: sum of alpha * color, sum of alpha, product of (1 - alpha).
struct TailAccum {
    weighted_color: vec3f,
    alpha_sum: f32,
    transmittance: f32,
}

fn tail_empty() -> TailAccum {
    return TailAccum(vec3f(0.0), 0.0, 1.0);
}

fn tail_accumulate(tail: TailAccum, color: vec3f, alpha: f32) -> TailAccum {
    let a = saturate(alpha);
    return TailAccum(tail.weighted_color + a * color, tail.alpha_sum + a, tail.transmittance * (1.0 - a));
}

// The tail as one premultiplied color: a = 1 - transmittance, color = weighted mean.
fn tail_resolve(tail: TailAccum) -> vec4f {
    if tail.alpha_sum <= 0.0 {
        return vec4f(0.0);
    }
    let a = 1.0 - tail.transmittance;
    let color = tail.weighted_color / tail.alpha_sum;
    return vec4f(color * a, a);
}

// acc.rgb + (1 - acc.a) * background.
fn composite_over_background(acc: vec4f, background: vec3f) -> vec3f {
    return acc.rgb + (1.0 - acc.a) * background;
}
