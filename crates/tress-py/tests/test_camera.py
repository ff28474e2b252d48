"""Each camera projects points as plain numpy projection math says it should."""

import math

import numpy as np
import pytest

import tress

RNG = np.random.default_rng(5)


def _rotation(rng):
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def test_opencv_camera_projects_like_k_r_t():
    K = np.array([[812.0, 0.0, 301.5], [0.0, 790.0, 250.25], [0.0, 0.0, 1.0]])
    R = _rotation(RNG)
    t = np.array([0.3, -0.2, 40.0])
    cam = tress.Camera.from_opencv(K, R, t, 640, 480)
    pts = RNG.normal(scale=5.0, size=(200, 3))
    x = pts @ R.T + t  # camera space, z forward
    uv_expected = (x @ K.T)[:, :2] / x[:, 2:3]
    uv, depth = cam.project(pts)
    np.testing.assert_allclose(uv, uv_expected, atol=1e-6)
    np.testing.assert_allclose(depth, x[:, 2], atol=1e-9)
    np.testing.assert_allclose(cam.K, K, atol=1e-9)
    np.testing.assert_allclose(cam.R, R, atol=1e-12)
    np.testing.assert_allclose(cam.t, t, atol=1e-12)


def test_opencv_camera_with_skew():
    K = np.array([[500.0, 3.0, 100.0], [0.0, 520.0, 90.0], [0.0, 0.0, 1.0]])
    cam = tress.Camera.from_opencv(K, np.eye(3), np.array([0.0, 0.0, 10.0]), 200, 180)
    pts = RNG.normal(size=(50, 3))
    x = pts + [0, 0, 10]
    uv_expected = (x @ K.T)[:, :2] / x[:, 2:3]
    np.testing.assert_allclose(cam.project(pts)[0], uv_expected, atol=1e-6)


def test_look_at_is_a_centred_pinhole():
    eye, target = np.array([30.0, 10.0, 45.0]), np.array([0.0, -3.0, 0.0])
    W, H, fov = 320, 240, 40.0
    cam = tress.Camera.look_at(eye, target, (0, 1, 0), fov, W, H)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0, 1, 0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)  # OpenCV's y points down
    f = H / 2 / math.tan(math.radians(fov) / 2)
    pts = target + RNG.normal(scale=8.0, size=(100, 3))
    d = pts - eye
    z = d @ forward
    u = f * (d @ right) / z + W / 2 - 0.5
    v = f * (d @ down) / z + H / 2 - 0.5
    uv, depth = cam.project(pts)
    np.testing.assert_allclose(uv, np.stack([u, v], 1), atol=1e-6)
    np.testing.assert_allclose(depth, z, atol=1e-9)
    np.testing.assert_allclose(cam.eye, eye, atol=1e-9)
    np.testing.assert_allclose(cam.K, [[f, 0, W / 2 - 0.5], [0, f, H / 2 - 0.5], [0, 0, 1]], atol=1e-9)


def test_orthographic_camera_scales_by_extent():
    W, H, extent = 256, 128, 20.0
    cam = tress.Camera.orthographic((0, 0, 50), (0, 0, 0), (0, 1, 0), extent, W, H)
    assert cam.is_orthographic
    pts = RNG.normal(scale=4.0, size=(60, 3))
    scale = H / extent  # pixels per world unit
    u = W / 2 + pts[:, 0] * scale - 0.5
    v = H / 2 - pts[:, 1] * scale - 0.5
    uv, depth = cam.project(pts)
    np.testing.assert_allclose(uv, np.stack([u, v], 1), atol=1e-6)
    np.testing.assert_allclose(depth, 50 - pts[:, 2], atol=1e-9)
    with pytest.raises(ValueError, match="no pinhole"):
        cam.K


def test_orbit_circles_the_target():
    cams = tress.orbit(16, radius=60.0, elevation=10.0, target=(0, -5, 0), width=64, height=48)
    assert len(cams) == 16
    eyes = np.array([c.eye for c in cams])
    np.testing.assert_allclose(np.linalg.norm(eyes - [0, -5, 0], axis=1), 60.0, atol=1e-9)
    np.testing.assert_allclose(eyes[:, 1], -5 + 60 * math.sin(math.radians(10)), atol=1e-9)
    np.testing.assert_allclose(eyes[0], [0, -5 + 60 * math.sin(math.radians(10)), 60 * math.cos(math.radians(10))],
                               atol=1e-9)
    # The target projects to the image centre from every view.
    for c in cams:
        uv, _ = c.project(np.array([[0.0, -5.0, 0.0]]))
        np.testing.assert_allclose(uv[0], [31.5, 23.5], atol=1e-9)


def test_bad_cameras_say_why():
    with pytest.raises(ValueError, match="rotation"):
        tress.Camera.from_opencv(np.eye(3), np.eye(3) * 2, np.zeros(3), 10, 10)
    with pytest.raises(ValueError, match=r"\(3, 3\)"):
        tress.Camera.from_opencv(np.eye(4), np.eye(3), np.zeros(3), 10, 10)
    with pytest.raises(ValueError, match="eye and target"):
        tress.Camera.look_at((1, 2, 3), (1, 2, 3))
    with pytest.raises(ValueError, match="width and height"):
        tress.Camera.look_at((0, 0, 10), width=0)
    with pytest.raises(ValueError, match="parallel"):
        tress.Camera.look_at((0, 10, 0), (0, 0, 0), (0, 1, 0))
