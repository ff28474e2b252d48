// ShortCut threshold pass (after TressFX 4.1's "ResolveDepth"): after the depth pass, copy each
// pixel's k-th nearest key (layer k - 1) into `shortcut_far`, so the shade pass tells a tail
// fragment (farther than the k-th) with one load, before the layers are claimed. A compute pass
// over the pixels; k and the pixel count come from the buffers' lengths. Owner:
// `ShortcutThreshold`.

@group(0) @binding(0) var<storage, read_write> shortcut_keys: array<atomic<u32>>;
@group(0) @binding(1) var<storage, read_write> shortcut_far: array<u32>;

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixels = arrayLength(&shortcut_far);
    let p = id.x + id.y * 65535u * 64u;
    if p >= pixels {
        return;
    }
    let k = arrayLength(&shortcut_keys) / pixels;
    shortcut_far[p] = atomicLoad(&shortcut_keys[(k - 1u) * pixels + p]);
}
