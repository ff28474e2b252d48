"""The CPU reference path tracer against the GPU's coverage and the cameras' projection, and
voxelize against an independent numpy sampling of the strands."""

import numpy as np
import pytest

import tress

W, H = 48, 36


@pytest.fixture(scope="module")
def groom():
    hair = tress.generate("straight", strands=300, vertices=12, seed=3)
    lo, hi = hair.points.min(axis=0), hair.points.max(axis=0)
    return hair, (lo + hi) / 2, float(np.linalg.norm(hi - lo))


def _camera(groom, **kw):
    hair, centre, diag = groom
    return tress.Camera.look_at(centre + np.array([0.3, 0.2, 1.0]) * diag, centre, (0, 1, 0), 40.0, W, H,
                                near=0.05 * diag, far=10 * diag, **kw)


def test_path_trace_shape_dtype_and_determinism(renderer):
    r = renderer
    hair = tress.generate("straight", strands=300, vertices=12, seed=3)
    lo, hi = hair.points.min(axis=0), hair.points.max(axis=0)
    centre, diag = (lo + hi) / 2, float(np.linalg.norm(hi - lo))
    cams = tress.orbit(2, radius=1.2 * diag, target=centre, width=W, height=H)
    a = r.path_trace(hair, cams, spp=4, seed=5)
    assert a.shape == (2, H, W, 3) and a.dtype == np.float32
    assert np.all(np.isfinite(a)) and a.max() > 0
    np.testing.assert_array_equal(a, r.path_trace(hair, cams, spp=4, seed=5))
    assert not np.array_equal(a, r.path_trace(hair, cams, spp=4, seed=6))
    kk = r.path_trace(hair, cams[0], spp=4, shading="kajiya-kay", background=(0.2, 0.3, 0.4))
    assert kk.shape == (1, H, W, 3)
    np.testing.assert_allclose(kk[0, 0, 0], (0.2, 0.3, 0.4), atol=1e-6)  # a corner misses the hair
    blond = r.path_trace(hair, cams[0], spp=4, fiber={"eumelanin": 0.1, "beta_m": 0.3})
    assert blond.mean() > a[0].mean()
    # The head the strands grow from fills pixels between them.
    bare = np.any(kk[0] != kk[0, 0, 0], axis=-1).sum()
    headed = r.path_trace(hair, cams[0], spp=2, shading="kajiya-kay", head="generated", background=(0.2, 0.3, 0.4))
    assert np.any(headed[0] != kk[0, 0, 0], axis=-1).sum() > bare


def test_path_trace_rejects_bad_arguments(renderer, groom):
    r = renderer
    hair, cam = groom[0], _camera(groom)
    with pytest.raises(ValueError, match="melanin.*valid: eumelanin"):
        r.path_trace(hair, cam, spp=1, fiber={"melanin": 1.0})
    with pytest.raises(ValueError, match="shading"):
        r.path_trace(hair, cam, spp=1, shading="phong")
    with pytest.raises(ValueError, match="beta_m"):
        r.path_trace(hair, cam, spp=1, fiber={"beta_m": 5.0})
    with pytest.raises(ValueError, match="spp"):
        r.path_trace(hair, cam, spp=0)
    with pytest.raises(ValueError, match="bounces"):
        r.path_trace(hair, cam, spp=1, settings={"trace.bounces": -1})


def test_path_trace_silhouette_matches_the_gpu_alpha(renderer, groom):
    hair, cam = groom[0], _camera(groom)
    # The GPU draws strands `strands.width_px` wide; the tracer's physical width (the generated
    # strands' thickness) is far below a pixel here, so 4 samples find a few percent of the
    # strands' pixels. `trace.width = screen` traces the GPU's ink width instead. Measured
    # IoU: 0.92 at 4 spp (0.98 at 16), with the GPU's coverage above 0.05.
    traced = renderer.path_trace(hair, cam, spp=4, shading="kajiya-kay", settings={"trace.width": "screen"})[0]
    alpha = renderer.render(hair, cam, maps=("alpha",))["alpha"][0, :, :, 0]
    hit = np.any(traced != 0, axis=-1)
    gpu = alpha > 0.05
    iou = (hit & gpu).sum() / (hit | gpu).sum()
    assert gpu.sum() > 0.05 * W * H
    assert iou > 0.85, iou


def test_path_trace_honours_an_off_centre_principal_point(renderer, groom):
    """from_opencv cameras whose principal points differ by (6, -4) pixels: the image moves by
    what Camera.project predicts, and the hair's centroid lands where project puts it."""
    hair, centre, diag = groom
    r = renderer
    base = _camera(groom)
    K = base.K
    shifted_K = K.copy()
    shifted_K[0, 2] += 6.0
    shifted_K[1, 2] -= 4.0
    cams = [tress.Camera.from_opencv(k, base.R, base.t, W, H, near=0.05 * diag, far=10 * diag) for k in (K, shifted_K)]
    d = cams[1].project(hair.points)[0] - cams[0].project(hair.points)[0]
    np.testing.assert_allclose(d, np.tile([6.0, -4.0], (len(d), 1)), atol=1e-3)
    img = r.path_trace(hair, cams, spp=4, shading="kajiya-kay", settings={"trace.width": "screen"})
    hit = np.any(img != 0, axis=-1)
    # cy - 4 moves the image up 4 rows, cx + 6 right 6 columns. Per-pixel random streams and
    # stochastic transparency make single pixels differ; the masks overlap as the silhouette
    # test's do (measured IoU 0.89; unshifted 0.48).
    a, b = hit[1, :-4, 6:], hit[0, 4:, :-6]
    assert (a & b).sum() / (a | b).sum() > 0.85, (a & b).sum() / (a | b).sum()
    a0 = hit[1, :-4, :-6]
    assert (a0 & b).sum() / (a0 | b).sum() < 0.7
    # The GPU draws the off-centre camera's silhouette in the same place (measured IoU 0.9).
    gpu = renderer.render(hair, cams[1], maps=("alpha",))["alpha"][0, :, :, 0] > 0.05
    assert (gpu & hit[1]).sum() / (gpu | hit[1]).sum() > 0.85
    # The traced silhouette is where the points project (centroid within a pixel or two).
    uv = cams[1].project(hair.points)[0]
    rows, cols = np.nonzero(hit[1])
    inside = (uv[:, 0] > -0.5) & (uv[:, 0] < W - 0.5) & (uv[:, 1] > -0.5) & (uv[:, 1] < H - 0.5)
    assert abs(cols.mean() - uv[inside, 0].mean()) < 2.5 and abs(rows.mean() - uv[inside, 1].mean()) < 2.5


# -- voxelize ------------------------------------------------------------------------------

def _dense_hits(points, offsets, lo, hi, res, n=4001):
    """Voxels hit by a dense sampling of every segment, and the tangent per hit, by numpy."""
    d, h, w = res
    size = (hi - lo) / np.array([w, h, d])
    hits = np.zeros(res, dtype=bool)
    for s in range(len(offsets) - 1):
        p = points[offsets[s]:offsets[s + 1]].astype(np.float64)
        for a, b in zip(p[:-1], p[1:]):
            t = np.linspace(0, 1, n)[:, None]
            x = a + t * (b - a)
            v = np.floor((x - lo) / size).astype(int)
            ok = np.all((v >= 0) & (v < [w, h, d]), axis=1)
            hits[v[ok, 2], v[ok, 1], v[ok, 0]] = True
    return hits


def test_voxelize_matches_a_dense_numpy_sampling():
    rng = np.random.default_rng(1)
    # Straight strands in generic directions (none along a voxel boundary), 3 vertices each.
    roots = rng.uniform(-0.8, 0.8, (6, 3))
    dirs = rng.normal(size=(6, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    strands = np.stack([roots + k * 0.35 * dirs for k in range(3)], axis=1)
    hair = tress.Hair.from_padded(strands)
    lo, hi = np.array([-1.5, -1.2, -1.4]), np.array([1.5, 1.3, 1.2])
    res = (10, 14, 12)
    out = tress.voxelize(hair, bounds=(lo, hi), resolution=res, fields=("occupancy", "orientation", "density"))
    occ = out["occupancy"]
    assert occ.shape == res and occ.dtype == np.bool_
    assert out["orientation"].shape == res + (3,) and out["orientation"].dtype == np.float32
    np.testing.assert_allclose(out["bounds"][0], lo, atol=1e-6)
    np.testing.assert_array_equal(occ, _dense_hits(hair.points, hair.offsets, lo, hi, res))
    # Density: the strands' total length (all inside the box).
    np.testing.assert_allclose(out["density"].sum(), 6 * 0.7, rtol=1e-4)
    # Orientation: a voxel crossed by one strand only holds that strand's sign-normalised tangent
    # (the one pointing down, y < 0).
    alone = [_dense_hits(strands[s], np.array([0, 3]), lo, hi, res) for s in range(6)]
    for s in range(6):
        only = alone[s] & ~np.any([alone[o] for o in range(6) if o != s], axis=0)
        assert only.any()
        t = dirs[s] * (-1 if dirs[s, 1] > 0 else 1)
        np.testing.assert_allclose(out["orientation"][only], np.tile(t, (only.sum(), 1)), atol=1e-5)
    assert np.all(out["orientation"][~occ] == 0)
    np.testing.assert_allclose(np.linalg.norm(out["orientation"][occ], axis=-1), 1.0, atol=1e-5)


def test_voxelize_axes_and_default_bounds():
    # One strand along +x at a known y and z: it fills one row along the W axis.
    hair = tress.Hair.from_padded([[[0.06, 0.31, -0.42], [0.94, 0.31, -0.42]]])
    lo, hi = np.array([0.0, 0.0, -1.0]), np.array([1.0, 1.0, 0.0])
    out = tress.voxelize(hair, bounds=(lo, hi), resolution=(5, 10, 20))
    d, h, w = np.nonzero(out["occupancy"])
    assert set(d) == {2} and set(h) == {3}  # z = -0.42 -> (0.58 * 5) = 2; y = 0.31 -> 3
    assert list(w) == list(range(1, 19))  # x from 0.06 to 0.94: voxels 1..18 of 20
    np.testing.assert_allclose(out["orientation"][2, 3, 1:19], np.tile([1, 0, 0], (18, 1)), atol=1e-6)
    # Default: the hair's box grown by one voxel per side, at the default (96, 128, 128).
    groom = tress.generate("straight", strands=50, vertices=8, seed=1)
    out = tress.voxelize(groom)
    assert out["occupancy"].shape == (96, 128, 128) and set(out) == {"occupancy", "orientation", "bounds"}
    blo, bhi = groom.points.min(axis=0), groom.points.max(axis=0)
    size = (out["bounds"][1] - out["bounds"][0]) / np.array([128, 128, 96])
    np.testing.assert_allclose(out["bounds"][0], blo - size, rtol=1e-4, atol=1e-4)
    np.testing.assert_allclose(out["bounds"][1], bhi + size, rtol=1e-4, atol=1e-4)
    occ = out["occupancy"]
    assert not occ[0].any() and not occ[-1].any() and not occ[:, 0].any() and not occ[:, :, -1].any()
    assert occ[1].any() or occ[-2].any()


def test_voxelize_rejects_bad_arguments():
    hair = tress.Hair.from_padded([[[0, 0, 0], [1, 1, 1]]])
    with pytest.raises(ValueError, match="resolution"):
        tress.voxelize(hair, resolution=(2, 128, 128))
    with pytest.raises(ValueError, match="resolution"):
        tress.voxelize(hair, resolution=(96, 128))
    with pytest.raises(ValueError, match="bounds"):
        tress.voxelize(hair, bounds=((0, 0, 0), (1, 0, 1)))
    with pytest.raises(ValueError, match="bounds"):
        tress.voxelize(hair, bounds=(0, 1))
    with pytest.raises(ValueError, match="fields"):
        tress.voxelize(hair, fields=("occupancy", "curvature"))
