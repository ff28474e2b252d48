import subprocess
import threading
import time

import numpy as np
import pytest

import tress
from plain_hair_reader import read_hair

WRITES = [".hair", ".tfx", ".usda", ".usdc", ".usd", ".abc", ".data"]


@pytest.fixture(scope="module")
def groom():
    return tress.generate("wavy", strands=300, vertices=12, seed=7)


def test_generate_matches_the_cli(tmp_path, tress_bin, groom):
    out = tmp_path / "cli.hair"
    subprocess.run([tress_bin, "generate", "wavy", "--strands", "300", "--vertices", "12",
                    "--seed", "7", "-o", out], check=True, capture_output=True)
    cli = read_hair(out)  # read by the plain-Python reader, not by tress
    assert len(groom) == len(cli) == 300
    np.testing.assert_allclose(groom.points, np.array([p for s in cli for p in s], dtype=np.float32),
                               atol=1e-6)


@pytest.mark.parametrize("ext", WRITES)
def test_save_and_load_every_written_format(tmp_path, groom, ext):
    path = tmp_path / f"groom{ext}"
    tress.save(path, groom)
    back = tress.load(path)
    assert back.points.dtype == np.float32 and back.offsets.dtype == np.int64
    assert back.points.flags.c_contiguous
    np.testing.assert_array_equal(back.offsets, groom.offsets)
    np.testing.assert_allclose(back.points, groom.points, atol=1e-4)


def test_load_agrees_with_a_plain_python_reader(tmp_path, groom):
    path = tmp_path / "g.hair"
    tress.save(path, groom)
    strands = read_hair(path)
    hair = tress.load(str(path))
    assert len(hair) == len(strands)
    for i in (0, 17, 299):
        np.testing.assert_array_equal(hair.strand(i), np.array(strands[i], dtype=np.float32))


def test_load_merges_files_in_order(tmp_path, groom):
    a, b = tmp_path / "a.hair", tmp_path / "b.tfx"
    tress.save(a, groom)
    tress.save(b, groom.resample(5))
    merged = tress.load([a, b])
    assert len(merged) == 600
    assert merged.offsets[300] == len(groom.points)
    np.testing.assert_allclose(merged.points[len(groom.points):], groom.resample(5).points, atol=1e-4)


def test_from_arrays_and_padded_round_trip():
    rng = np.random.default_rng(1)
    padded = rng.normal(size=(40, 9, 3))  # float64 in: converted
    hair = tress.Hair.from_padded(padded)
    assert len(hair) == 40 and hair.points.dtype == np.float32
    np.testing.assert_array_equal(hair.vertex_counts, np.full(40, 9))
    np.testing.assert_allclose(hair.to_padded(9), padded, atol=1e-5)
    again = tress.Hair.from_arrays(hair.points, hair.offsets.astype(np.int32))
    np.testing.assert_array_equal(again.offsets, hair.offsets)


def _arclength_resample(strand, n):
    """Independent numpy resampling: n points uniformly spaced by arc length."""
    seg = np.linalg.norm(np.diff(strand, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.linspace(0.0, s[-1], n)
    return np.stack([np.interp(t, s, strand[:, k]) for k in range(3)], axis=1)


def test_resample_by_arclength_matches_numpy(groom):
    res = groom.resample(7)
    assert len(res) == len(groom)
    np.testing.assert_array_equal(res.vertex_counts, np.full(len(groom), 7))
    for i in (0, 100, 299):
        np.testing.assert_allclose(res.strand(i), _arclength_resample(groom.strand(i).astype(np.float64), 7),
                                   atol=1e-4)
    padded = groom.to_padded(5)
    assert padded.shape == (300, 5, 3)


def test_follow_hairs_multiply_the_strands(groom):
    f = groom.follow(3, seed=2)
    assert len(f) == 4 * len(groom)
    # Each guide comes first, unchanged, followed by its followers.
    np.testing.assert_array_equal(f.strand(0), groom.strand(0))
    np.testing.assert_array_equal(f.strand(4), groom.strand(1))


def test_bounds_and_len(groom):
    lo, hi = groom.bounds
    np.testing.assert_array_equal(lo, groom.points.min(axis=0))
    np.testing.assert_array_equal(hi, groom.points.max(axis=0))
    assert len(groom) == 300 and "300 strands" in repr(groom)


def test_styles_and_unknown_style():
    assert tress.styles() == ["straight", "wavy", "curly", "ponytail", "fur"]
    with pytest.raises(ValueError, match="straight, wavy, curly, ponytail, fur"):
        tress.generate("afro")
    with pytest.raises(TypeError, match="curl_radius"):
        tress.generate("wavy", curliness=2)


# --- bad input -------------------------------------------------------------------------


def test_wrong_shapes_and_dtypes_name_the_argument():
    with pytest.raises(ValueError, match=r"points must have shape \(P, 3\), got \(10, 2\)"):
        tress.Hair.from_arrays(np.zeros((10, 2)), [0, 10])
    with pytest.raises(TypeError, match="points must be a numeric array"):
        tress.Hair.from_arrays(np.array([["a", "b", "c"]]), [0, 1])
    with pytest.raises(ValueError, match="offsets must run from 0 to len"):
        tress.Hair.from_arrays(np.zeros((10, 3)), [0, 4, 9])
    with pytest.raises(ValueError, match="offsets must increase"):
        tress.Hair.from_arrays(np.zeros((10, 3)), [0, 4, 4, 10])
    with pytest.raises(ValueError, match=r"thickness must have shape \(10,\)"):
        tress.Hair.from_arrays(np.zeros((10, 3)), [0, 10], thickness=np.ones(9))
    with pytest.raises(ValueError, match=r"strands must have shape \(N, V, 3\)"):
        tress.Hair.from_padded(np.zeros((4, 3)))
    with pytest.raises(TypeError, match="tress.Hair"):
        tress.save("x.hair", np.zeros((3, 3)))


def test_non_finite_points_are_a_value_error(tmp_path):
    pts = np.zeros((4, 3), dtype=np.float32)
    pts[2, 1] = np.nan
    hair = tress.Hair.from_arrays(pts, [0, 4])
    with pytest.raises(ValueError, match="finite"):
        tress.save(tmp_path / "nan.hair", hair)


def _cli_error(tress_bin, path):
    r = subprocess.run([tress_bin, "info", path], capture_output=True, text=True)
    assert r.returncode == 2
    line = r.stderr.strip()
    assert line.startswith("tress: ") and "\n" not in line
    return line[len("tress: "):]


@pytest.mark.parametrize("name,data", [
    ("truncated.hair", b"HAIR" + b"\x05\x00\x00\x00" * 3),
    ("garbage.tfx", b"\x00\x01" * 50),
    ("broken.usda", b"#usda 1.0\n(\n def Curves \"x\" { float3[] points = [(1,2\n"),
    ("noise.abc", bytes(range(256)) * 4),
    ("short.data", b"\x10\x00"),
])
def test_corrupt_files_raise_hair_error_with_the_cli_line(tmp_path, tress_bin, name, data):
    path = tmp_path / name
    path.write_bytes(data)
    with pytest.raises(tress.HairError) as e:
        tress.load(path)
    assert str(e.value) == _cli_error(tress_bin, path)
    assert str(path) in str(e.value)


def test_unknown_extension_names_the_formats(tmp_path):
    with pytest.raises(tress.HairError, match=r"\.hair, \.tfx"):
        tress.load(tmp_path / "x.obj")
    with pytest.raises(tress.HairError, match="No such file"):
        tress.load(tmp_path / "missing.hair")


def test_fuzzing_regressions_never_crash(tmp_path):
    """Every hostile file the fuzzers kept, and every seed, loads or raises HairError or ValueError (a crash would end
    pytest itself)."""
    from conftest import ROOT

    readers = {"read_usd": ".usdc", "read_abc": ".abc", "read_hair": ".hair", "read_tfx": ".tfx",
               "read_data": ".data", "read_ct2hair": ".bin"}
    tried = 0
    for reader, ext in readers.items():
        kept = sorted((ROOT / "fuzz" / "regressions" / reader).glob("*"))
        seeds = sorted((ROOT / "fuzz" / "seeds" / reader).glob("*"))
        for i, p in enumerate(kept + seeds):
            if not p.is_file():
                continue
            copy = tmp_path / f"{reader}-{i}{ext}"
            copy.write_bytes(p.read_bytes())
            try:
                tress.load(copy)
            except (tress.HairError, ValueError):
                pass
            tried += 1
    assert tried >= 20


def test_reading_releases_the_gil():
    """A thread generating 150k strands lets the main thread's Python run meanwhile."""
    done = threading.Event()
    ticks = 0

    def work():
        tress.generate("ponytail", strands=150_000, vertices=13, seed=1)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    start = time.perf_counter()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    elapsed = time.perf_counter() - start
    # Without releasing the GIL the loop would not run while generate holds it.
    assert elapsed > 0.05 and ticks > elapsed * 100, (ticks, elapsed)
