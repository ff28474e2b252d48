"""Renders as arrays, checked against `tress render`, against the cameras' own projection and
against compositing."""

import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import tress

W, H = 160, 120


@pytest.fixture(scope="module")
def groom():
    return tress.generate("straight", strands=3000, vertices=16, seed=4)


def test_rgb_equals_what_tress_render_writes(tmp_path, tress_bin, renderer, groom):
    tress.save(tmp_path / "g.hair", groom)
    eye, target, fov, bg = (28.0, 6.0, 42.0), (0.0, -8.0, 0.0), 38.0, (0.2, 0.22, 0.25)
    (tmp_path / "scene.toml").write_text(f"""
background = {list(bg)}
[camera]
eye = {list(eye)}
target = {list(target)}
fov_y_deg = {fov}
near = 1.0
far = 300.0
[[hair]]
files = ["g.hair"]
[output]
width = {W}
height = {H}
""")
    png = tmp_path / "cli.png"
    subprocess.run([tress_bin, "render", tmp_path / "scene.toml", "-o", png], check=True,
                   capture_output=True)
    cli = np.asarray(Image.open(png).convert("RGB"))
    cam = tress.Camera.look_at(eye, target, (0, 1, 0), fov, W, H, near=1.0, far=300.0)
    # A scene without [head] grows its hair files on the generated head.
    out = renderer.render(groom, [cam], maps=("rgb",), background=bg, rgb_format="srgb8",
                          head="generated")
    ours = out["rgb"][0]
    assert ours.shape == cli.shape and ours.dtype == np.uint8
    diff = np.abs(ours.astype(int) - cli.astype(int))
    # Equal but for the order of blended fragments (GPU atomics): a level or two in a few pixels.
    assert diff.max() <= 2 and (diff > 1).mean() < 1e-3, (diff.max(), (diff > 1).mean())
    # The frame shows hair: a good part of it differs from the background.
    assert (np.abs(cli.astype(int) - cli[0, 0]).sum(axis=2) > 10).mean() > 0.05


def _distance_to_segment(p, a, b):
    ab = b - a
    t = np.clip(((p - a) @ ab) / (ab @ ab), 0, 1)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


@pytest.mark.parametrize("kind", ["opencv", "orthographic"])
def test_coverage_lies_on_the_projected_strand(renderer, kind):
    """One straight strand: the pixels it covers are those its projection (Camera.project,
    plain numpy) passes through."""
    a, b = np.array([-6.0, -4.0, 1.0]), np.array([5.0, 3.5, -2.0])
    pts = np.linspace(a, b, 12)
    hair = tress.Hair.from_arrays(pts, [0, 12], thickness=np.full(12, 0.05))
    if kind == "opencv":
        K = np.array([[150.0, 0.0, 70.0], [0.0, 150.0, 66.0], [0.0, 0.0, 1.0]])
        cam = tress.Camera.from_opencv(K, np.eye(3), np.array([0.0, 0.0, 30.0]), W, H, near=1.0)
    else:
        cam = tress.Camera.orthographic((3, 2, 30), (0, 0, 0), (0, 1, 0), 20.0, W, H, near=1.0)
    alpha = renderer.render(hair, [cam], maps=("alpha",))["alpha"][0, :, :, 0]
    (ua, _), (ub, _) = cam.project(a[None]), cam.project(b[None])
    ua, ub = ua[0], ub[0]
    covered = np.argwhere(alpha > 0.3)[:, ::-1].astype(float)  # (u, v) = (column, row)
    assert len(covered) > 0.6 * np.linalg.norm(ub - ua)
    assert _distance_to_segment(covered, ua, ub).max() < 1.6
    # ... and the projection's pixels are covered, away from the ends.
    for s in np.linspace(0.1, 0.9, 9):
        u, v = np.round(ua + s * (ub - ua)).astype(int)
        assert alpha[max(v - 1, 0):v + 2, max(u - 1, 0):u + 2].max() > 0.3, (s, u, v)


def test_alpha_is_the_coverage_compositing_uses(renderer, groom):
    """Over black and over white: rgb_white − rgb_black = 1 − alpha (premultiplied 'over')."""
    cam = tress.Camera.look_at((0, 0, 60), (0, -8, 0), width=W, height=H)
    black = renderer.render(groom, cam, background=(0, 0, 0), head="generated")
    white = renderer.render(groom, cam, background=(1, 1, 1), head="generated")
    np.testing.assert_allclose(black["alpha"], white["alpha"], atol=1e-3)
    expected = 1.0 - black["alpha"][..., 0]
    got = (white["rgb"] - black["rgb"]).mean(axis=-1)
    assert np.abs(got - expected)[0].mean() < 0.01
    assert np.abs(got - expected).max() < 0.05
    assert (black["alpha"] > 0.99).mean() > 0.05  # the head is opaque
    assert (black["alpha"] < 0.01).mean() > 0.2  # and the background empty


def test_many_views_come_back_as_one_array(renderer, groom):
    cams = tress.orbit(3, 60.0, 10.0, (0, -8, 0), width=64, height=48)
    out = renderer.render(groom, cams, technique="volume")
    assert out["rgb"].shape == (3, 48, 64, 3) and out["alpha"].shape == (3, 48, 64, 1)
    assert out["rgb"].dtype == np.float32
    # Different views, different pictures.
    assert np.abs(out["alpha"][0] - out["alpha"][1]).mean() > 0.01


def test_bad_render_arguments(renderer, groom):
    cam = tress.Camera.look_at((0, 0, 60), width=32, height=32)
    with pytest.raises(ValueError, match="valid maps: rgb, alpha"):
        renderer.render(groom, cam, maps=("rgb", "normals"))
    with pytest.raises(ValueError, match="valid: strands, volume"):
        renderer.render(groom, cam, technique="raytrace")
    with pytest.raises(ValueError, match="every camera must be 32x32"):
        renderer.render(groom, [cam, tress.Camera.look_at((0, 0, 60), width=16, height=32)])
    with pytest.raises(TypeError, match="tress.Hair"):
        renderer.render(groom.points, cam)
    with pytest.raises(ValueError, match="kajiya-kay, scheuermann or marschner"):
        renderer.render(groom, cam, settings={"strands.shading": "phong"})
    with pytest.raises(ValueError, match="head faces must index"):
        renderer.render(groom, cam, head=(np.zeros((3, 3)), [[0, 1, 7]]))


def test_no_adapter_says_how_to_install_a_driver():
    env = dict(os.environ, VK_DRIVER_FILES="/nonexistent/icd.json", VK_ICD_FILENAMES="/nonexistent/icd.json",
               WGPU_BACKEND="vulkan")
    code = ("import tress\n"
            "try:\n    tress.Renderer()\nexcept RuntimeError as e:\n    print('RuntimeError:', e)\n")
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert "RuntimeError:" in r.stdout and "mesa-vulkan-drivers" in r.stdout, (r.stdout, r.stderr)
