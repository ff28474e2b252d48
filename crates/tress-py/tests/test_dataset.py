"""tress.render_dataset: the local process pool and Dask render the same files, failures are
collected, runs resume."""

import json
import os
import shutil

import numpy as np
import pytest

import tress

W, H = 64, 48
STYLES = ("straight", "wavy", "curly")


@pytest.fixture(scope="module")
def cameras():
    return tress.orbit(2, radius=60, elevation=10, target=(0, -5, 0), width=W, height=H)


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    d = tmp_path_factory.mktemp("grooms")
    paths = []
    for i, style in enumerate(STYLES):
        p = d / f"{style}.hair"
        tress.save(p, tress.generate(style, strands=400, seed=i))
        paths.append(str(p))
    bad = d / "corrupt.hair"
    bad.write_bytes(b"HAIR" + bytes(60))  # shorter than the 128-byte header
    paths.append(str(bad))
    return paths


@pytest.fixture(scope="module")
def local(tmp_path_factory, inputs, cameras):
    out = tmp_path_factory.mktemp("local")
    summary = tress.render_dataset(inputs, cameras, out, maps=("rgb", "alpha"), engine="local",
                                   progress=False)
    return out, summary


def _corrupt_line(inputs):
    with pytest.raises(tress.HairError) as e:
        tress.load(inputs[-1])
    return str(e.value)


def test_local_writes_every_map_and_collects_the_failure(local, inputs):
    out, summary = local
    assert summary["done"] == 3 and summary["skipped"] == 0, summary
    # The corrupt file is reported with the line tress.load raises, the others still rendered.
    assert summary["failed"] == [("corrupt", _corrupt_line(inputs))]
    assert summary["failed"][0][1].startswith(inputs[-1]) and "128-byte header" in summary["failed"][0][1]
    assert summary["seconds"] > 0
    for style in STYLES:
        d = out / style
        marker = json.loads((d / "done.json").read_text())
        assert marker["views"] == 2 and marker["maps"] == ["alpha", "rgb"]
        for v in range(2):
            rgb = np.load(d / f"{v:03d}_rgb.npy")
            alpha = np.load(d / f"{v:03d}_alpha.npy")
            assert rgb.shape == (H, W, 3) and rgb.dtype == np.float32
            assert alpha.shape == (H, W, 1) and alpha.dtype == np.float32
            assert 0.02 < (alpha > 0).mean() < 0.9  # the groom is in the frame
            assert f"{v:03d}_rgb.npy" in marker["files"] and f"{v:03d}_alpha.npy" in marker["files"]
            try:
                from PIL import Image
            except ImportError:
                continue
            png = np.asarray(Image.open(d / f"{v:03d}_rgb.png"))
            assert png.shape == (H, W, 3) and png.dtype == np.uint8
    assert not (out / "corrupt" / "done.json").exists()
    assert not [p for p in out.rglob("*.tmp")]


def test_a_second_run_skips_and_redraws_only_what_is_missing(tmp_path, local, inputs, cameras):
    src, _ = local
    out = tmp_path / "out"
    shutil.copytree(src, out)
    again = tress.render_dataset(inputs, cameras, out, progress=False)
    assert again["done"] == 0 and again["skipped"] == 3, again
    assert [g for g, _ in again["failed"]] == ["corrupt"]

    removed = out / "wavy" / "001_alpha.npy"
    removed.unlink()
    before = {p: p.stat().st_mtime_ns for p in out.rglob("*.npy")}
    third = tress.render_dataset(inputs, cameras, out, progress=False)
    assert third["done"] == 1 and third["skipped"] == 2, third
    assert np.array_equal(np.load(removed), np.load(src / "wavy" / "001_alpha.npy"))
    # The other grooms' files were not touched.
    for p, t in before.items():
        if p.parent.name != "wavy":
            assert p.stat().st_mtime_ns == t, p

    # Other maps (or cameras) are other outputs: everything is drawn again.
    alpha_only = tress.render_dataset(inputs, cameras, out, maps=("alpha",), progress=False)
    assert alpha_only["done"] == 3 and alpha_only["skipped"] == 0, alpha_only
    assert json.loads((out / "straight" / "done.json").read_text())["maps"] == ["alpha"]


def test_dask_renders_what_the_local_engine_renders(tmp_path, local, inputs, cameras):
    # Not importorskip: CI installs distributed, and a missing engine must fail the suite.
    import distributed  # noqa: F401

    src, local_summary = local
    out = tmp_path / "dask"
    summary = tress.render_dataset(inputs, cameras, out, engine="dask", workers=2, progress=False)
    assert summary["done"] == 3 and summary["skipped"] == 0, summary
    assert summary["failed"] == local_summary["failed"]
    files = sorted(p.relative_to(src) for p in src.rglob("*.npy"))
    assert len(files) == 3 * 2 * 2
    assert files == sorted(p.relative_to(out) for p in out.rglob("*.npy"))
    for f in files:
        a, b = np.load(src / f), np.load(out / f)
        assert a.shape == b.shape and a.dtype == b.dtype, f
        if "alpha" in f.name:
            assert np.array_equal(a, b), f
        else:
            # Blended fragments may meet in another order (GPU atomics): the last bits may differ.
            assert np.abs(a - b).max() <= 1e-3, (f, np.abs(a - b).max())


def test_in_process_hair_sources_equal_a_direct_render(tmp_path, renderer, cameras):
    hair = tress.generate("straight", strands=300, seed=9)
    summary = tress.render_dataset([("mine", hair)], cameras[:1], tmp_path, maps=("alpha",),
                                   workers=0, progress=False, background=(0.1, 0.2, 0.3))
    assert summary == {"done": 1, "skipped": 0, "failed": [], "seconds": summary["seconds"]}
    direct = renderer.render(hair, cameras[:1], maps=("alpha",), background=(0.1, 0.2, 0.3))
    assert np.array_equal(np.load(tmp_path / "mine" / "000_alpha.npy"), direct["alpha"][0])
    assert sorted(os.listdir(tmp_path / "mine")) == ["000_alpha.npy", "done.json"]


def test_arguments_are_checked_before_any_render(tmp_path, cameras, inputs):
    with pytest.raises(ValueError, match="unknown map"):
        tress.render_dataset(inputs, cameras, tmp_path, maps=("rgb", "nope"), progress=False)
    with pytest.raises(ValueError, match="unique"):
        tress.render_dataset([inputs[0], inputs[0]], cameras, tmp_path, progress=False)
    with pytest.raises(ValueError, match="engine"):
        tress.render_dataset(inputs, cameras, tmp_path, engine="ray", progress=False)
    with pytest.raises(TypeError, match="cameras"):
        tress.render_dataset(inputs, [], tmp_path, progress=False)
    assert os.listdir(tmp_path) == []
