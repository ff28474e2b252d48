// ShortCut resolve pass (after TressFX 4.1's "ShortCut"): a fullscreen pass that blends each
// pixel's claimed layers front to back (they are sorted by depth) and puts the tail under them:
// opacity `1 - T` with T the transmittance the shade pass multiplied up, color the weighted mean
// the shade pass added up (the tail's fragments from the k-th on, weighted by their estimated
// visibility), or that of the farthest layer where no tail fragment was weighted (see
// `tress_shading::resolve_shortcut`). Premultiplied, blended over the target (One,
// OneMinusSrcAlpha) like the PPLL resolve. Owner: `ShortcutResolve`.

#include "common/fullscreen.wgsl"
#include "common/camera.wgsl"
#include "common/params.wgsl"
#include "common/shading.wgsl"
#include "common/shortcut.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;
@group(3) @binding(4) var transmittance: texture_2d<f32>;
@group(3) @binding(6) var tail: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vertex_index);
}

@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<u32>(position.xy);
    let p = px.y * params.target_width + px.x;
    let pixels = shortcut_pixels(params);
    var acc = vec4<f32>(0.0);
    var farthest = vec3<f32>(0.0);
    var stored = 0u;
    for (var i = 0u; i + 1u < shortcut_k(params); i = i + 1u) {
        let v = atomicLoad(&shortcut_keys[i * pixels + p]);
        // Unclaimed layers (none when the passes saw the same fragments) are skipped.
        if (v & ALPHA_MASK) == 0u {
            continue;
        }
        let color = unpack_rgb9e5(shortcut_colors[i * pixels + p]);
        acc = blend_front_to_back(acc, color, shortcut_alpha(v));
        farthest = color;
        stored = stored + 1u;
    }
    let tail_alpha = 1.0 - textureLoad(transmittance, px, 0).r;
    let sums = textureLoad(tail, px, 0);
    let weighted = sums.rgb;
    let weight = sums.a;
    if stored == 0u && weight <= 0.0 {
        discard;
    }
    var tail_color = farthest;
    if weight > 0.0 {
        tail_color = weighted / weight;
    }
    return blend_under(acc, vec4<f32>(tail_color * tail_alpha, tail_alpha));
}
