"""Geometry maps against an independent numpy projection of the strands they name."""

import numpy as np
import pytest

import tress

W, H = 192, 144


@pytest.fixture(scope="module")
def scene(renderer):
    hair = tress.generate("wavy", strands=1500, vertices=24, seed=11)
    cam = tress.Camera.look_at((35.0, 4.0, 48.0), (0.0, -10.0, 0.0), (0, 1, 0), 40.0, W, H, near=1.0, far=300.0)
    out = renderer.render(hair, cam, maps=tress.MAPS[2:] + ("alpha",), head="generated")
    return hair, cam, out


def _nearest_segment(hair, cam, strand, pixel):
    """The projected segment of ``strand`` nearest to ``pixel`` (u, v): its angle θ (y up,
    directed root→tip) and the depth at the nearest point, by plain numpy."""
    pts = hair.strand(strand).astype(np.float64)
    uv, depth = cam.project(pts)
    a, b = uv[:-1], uv[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", pixel - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12), 0, 1)
    d = np.linalg.norm(a + t[:, None] * ab - pixel, axis=1)
    k = int(np.argmin(d))
    theta = np.arctan2(-(ab[k, 1]), ab[k, 0])
    # Depth is affine along the segment in world space; interpolate the perspective-correct way.
    za, zb = depth[k], depth[k + 1]
    tt = t[k]
    z = 1.0 / ((1 - tt) / za + tt / zb)
    return theta, z, d[k]


def test_orientation_and_depth_match_the_projected_strands(scene):
    hair, cam, out = scene
    ids = out["strand_id"][0, :, :, 0]
    angle = out["orientation"][0, :, :, 0]
    depth = out["depth"][0, :, :, 0]
    rows, cols = np.nonzero(ids >= 0)
    assert len(rows) > 0.03 * W * H
    rng = np.random.default_rng(0)
    pick = rng.choice(len(rows), size=min(600, len(rows)), replace=False)
    angle_err, depth_err, dist = [], [], []
    for i in pick:
        v, u = rows[i], cols[i]
        theta, z, d = _nearest_segment(hair, cam, ids[v, u], np.array([u, v], dtype=np.float64))
        e = abs(np.mod(theta, np.pi) - angle[v, u])
        angle_err.append(min(e, np.pi - e))
        depth_err.append(abs(z - depth[v, u]) / z)
        dist.append(d)
    angle_err, depth_err, dist = map(np.array, (angle_err, depth_err, dist))
    # Each covered pixel lies on the strand its id names...
    assert np.percentile(dist, 99) < 1.5, np.percentile(dist, 99)
    # ... with that strand's projected direction (stated bound: mean 1 degree) ...
    assert np.degrees(angle_err.mean()) < 1.0, np.degrees(angle_err.mean())
    assert np.degrees(np.percentile(angle_err, 95)) < 3.0
    # ... and its depth (mean 0.2 %).
    assert depth_err.mean() < 2e-3, depth_err.mean()


def test_masks_depth_and_ids_agree(scene):
    hair, cam, out = scene
    ids, mask, body = out["strand_id"][0], out["mask"][0], out["body_mask"][0]
    assert mask.dtype == np.bool_ and body.dtype == np.bool_ and ids.dtype == np.int32
    np.testing.assert_array_equal(mask, ids >= 0)
    assert ids.max() < len(hair) and ids.min() >= -1
    empty = ~mask & ~body
    assert np.all(np.isinf(out["depth"][0][empty])) and np.all(np.isfinite(out["depth"][0][~empty]))
    # The shaded frame covers the geometry maps' hair and head (lines are thinner than the
    # rendered strands' coverage, so the shaded coverage is at least the lines').
    alpha = out["alpha"][0]
    assert (alpha[mask | body] > 0.05).mean() > 0.97
    assert body.mean() > 0.05 and (body & mask).any()  # hair over the head


def test_encodings_follow_their_definitions(scene):
    _, _, out = scene
    d, mask, body = out["direction"], out["mask"], out["body_mask"]
    theta = np.arctan2(-d[..., 1:], d[..., :1])
    m = mask.astype(np.float32)
    hs = tress.encode_orientation(d, mask, body, "hairstep")
    np.testing.assert_allclose(hs[..., 0:1], np.where(mask, 1.0, np.where(body, 0.5, 0.0)), atol=1e-6)
    np.testing.assert_allclose(hs[..., 1:2], np.where(mask, (1 - np.cos(theta)) / 2, 0), atol=1e-6)
    np.testing.assert_allclose(hs[..., 2:3], np.where(mask, (1 + np.sin(theta)) / 2, 0), atol=1e-6)
    deg = tress.encode_orientation(d, mask, body, "angle_deg")
    assert deg.dtype == np.uint8 and deg.max() < 180
    ang = tress.encode_orientation(d, mask, body, "angle")
    diff = np.abs(deg.astype(float) - np.degrees(ang))
    assert np.all(np.minimum(diff, 180 - diff)[mask] <= 0.5 + 1e-3)
    mu = tress.encode_orientation(d, mask, body, "monohair_undirected")
    md = tress.encode_orientation(d, mask, body, "monohair")
    # Reversing every direction flips the directed map and leaves the undirected one.
    np.testing.assert_allclose(tress.encode_orientation(-d, mask, body, "monohair_undirected"), mu, atol=1e-5)
    flipped = tress.encode_orientation(-d, mask, body, "monohair")
    np.testing.assert_allclose((flipped[..., :2] + md[..., :2])[mask[..., 0]], 1.0, atol=1e-5)
    assert np.all(md[..., 2][mask[..., 0]] == 0.5)


def test_unknown_encoding_names_the_valid_ones(renderer):
    hair = tress.generate("straight", strands=50, vertices=4)
    cam = tress.Camera.look_at((0, 0, 60), width=16, height=16)
    with pytest.raises(ValueError, match="angle, angle_deg, hairstep, monohair, monohair_undirected"):
        renderer.render(hair, cam, maps=("orientation",), orientation="gabor")
