"""How fast ``tress.load`` reads a big .hair file into numpy, against the Rust reader and against
the plain-Python reader hair repositories write for themselves.

The file: the generated ponytail at the paper's scale, ``tress.generate("ponytail", vertices=16)``
(136,320 strands × 16 vertices, with per-vertex thickness), saved as .hair in a temporary folder.
Timed, best of ``--repeat`` (5):

* ``read bytes``: ``open(path, "rb").read()``, the file system's share (the page cache is warm);
* ``tress._tress.load``: the extension alone (read, parse, arrays handed to numpy);
* ``tress.load``: the Python API (the same, wrapped in a ``tress.Hair``);
* ``plain Python``: ``tests/plain_hair_reader.read_hair`` (``struct.unpack_from`` per point, as
  hair repositories do) and its list turned into an (N, V, 3) float32 array with ``np.array``;
* the Rust reader, ``Format::Hair.read`` on the same bytes in memory, and ``load_paths`` on the
  same file (the call ``tress.load`` makes, file read included): the fastest samples of
  ``cargo bench -p tress-hair --bench read -- read_hair_ponytail`` (``--cargo-bench`` runs it, or
  pass the in-memory time with ``--rust-ms``).

Targets (issue 18): ``tress.load`` within 2× of the Rust reader; at least 20× faster than the
plain-Python reader. Build the package in release for the first (``maturin develop --release``);
a debug build is enough for the second. ``--build`` names the build in the output.

    python crates/tress-py/bench/bench_load.py --build release --cargo-bench --json load.json
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

import tress

ROOT = pathlib.Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "crates" / "tress-py" / "tests"))
from plain_hair_reader import read_hair  # noqa: E402


def best(fn, repeat: int):
    times, result = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t)
        del result
    return min(times), times


def plain_python(path):
    strands = read_hair(path)
    return np.array(strands, dtype=np.float32)  # (N, V, 3): every strand has V vertices here


_UNITS = {"ns": 1e-9, "µs": 1e-6, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def cargo_bench_seconds() -> dict:
    """Runs divan's read_hair_ponytail benches; returns {name: (fastest, median, line)}, seconds."""
    cmd = ["cargo", "bench", "-q", "--locked", "-p", "tress-hair", "--bench", "read", "--",
           "read_hair_ponytail"]
    out = subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, text=True).stdout
    found = {}
    for line in out.splitlines():
        m = re.search(r"(read_hair_ponytail\w*)", line)
        vals = re.findall(r"([\d.]+)\s*(ns|µs|us|ms|s)\b", line)
        if m and len(vals) >= 3:
            fastest, _slowest, median = (float(v) * _UNITS[u] for v, u in vals[:3])
            found[m.group(1)] = (fastest, median, line.strip())
    if "read_hair_ponytail" not in found:
        raise RuntimeError(f"no read_hair_ponytail line in `{' '.join(cmd)}`'s output:\n{out}")
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--vertices", type=int, default=16)
    ap.add_argument("--build", default="unspecified", help="the package's build, for the record")
    ap.add_argument("--rust-ms", type=float, help="Format::Hair.read's time from cargo bench, ms")
    ap.add_argument("--cargo-bench", action="store_true", help="run cargo bench for the Rust time")
    ap.add_argument("--skip-plain", action="store_true", help="leave out the plain-Python reader")
    ap.add_argument("--json", type=pathlib.Path, help="write the results here")
    args = ap.parse_args()

    hair = tress.generate("ponytail", vertices=args.vertices)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "ponytail.hair")
        tress.save(path, hair)
        size = os.path.getsize(path)
        r = {"strands": len(hair), "vertices": int(len(hair.points)), "file_bytes": size,
             "build": args.build, "extension": tress._tress.__file__, "python": platform.python_version(),
             "numpy": np.__version__, "machine": platform.machine(), "cpus": os.cpu_count(),
             "repeat": args.repeat}
        del hair

        def read_bytes():
            with open(path, "rb") as f:
                return f.read()

        rows = []
        r["read_bytes_s"], _ = best(read_bytes, args.repeat)
        rows.append(("read bytes (open().read())", r["read_bytes_s"]))
        r["ext_load_s"], _ = best(lambda: tress._tress.load([path], 0, 4), args.repeat)
        rows.append(("tress._tress.load", r["ext_load_s"]))
        r["tress_load_s"], r["tress_load_all_s"] = best(lambda: tress.load(path), args.repeat)
        rows.append(("tress.load", r["tress_load_s"]))

        loaded = tress.load(path)
        if not args.skip_plain:
            r["plain_python_s"], r["plain_python_all_s"] = best(lambda: plain_python(path), args.repeat)
            rows.append(("plain Python struct reader + np.array", r["plain_python_s"]))
            plain = plain_python(path)
            assert np.array_equal(plain.reshape(-1, 3), loaded.points), "the readers disagree"
            r["plain_over_tress"] = r["plain_python_s"] / r["tress_load_s"]

    if args.cargo_bench:
        found = cargo_bench_seconds()
        r["rust_read_s"], r["rust_read_median_s"], r["rust_bench_line"] = found["read_hair_ponytail"]
        if "read_hair_ponytail_file" in found:
            (r["rust_load_file_s"], r["rust_load_file_median_s"],
             r["rust_file_bench_line"]) = found["read_hair_ponytail_file"]
    elif args.rust_ms is not None:
        r["rust_read_s"] = args.rust_ms / 1e3
    if "rust_read_s" in r:
        rows.append(("Rust Format::Hair.read (cargo bench, memory)", r["rust_read_s"]))
        r["tress_over_rust"] = r["tress_load_s"] / r["rust_read_s"]
    if "rust_load_file_s" in r:
        rows.append(("Rust load_paths (cargo bench, file)", r["rust_load_file_s"]))
        r["tress_over_rust_file"] = r["tress_load_s"] / r["rust_load_file_s"]

    print(f"{r['strands']:,} strands x {args.vertices} vertices, {size / 1e6:.1f} MB .hair; "
          f"package build: {args.build}; best of {args.repeat}")
    print(f"{'':46} {'seconds':>10} {'vs tress.load':>14}")
    for name, t in rows:
        print(f"{name:46} {t:10.4f} {t / r['tress_load_s']:13.2f}x")
    if "tress_over_rust" in r:
        ok = "met" if r["tress_over_rust"] <= 2 else "NOT met"
        print(f"tress.load / Rust reader = {r['tress_over_rust']:.2f} (target <= 2: {ok})")
    if "tress_over_rust_file" in r:
        ok = "met" if r["tress_over_rust_file"] <= 2 else "NOT met"
        print(f"tress.load / Rust load_paths of the file = {r['tress_over_rust_file']:.2f} "
              f"(target <= 2: {ok})")
    if "plain_over_tress" in r:
        ok = "met" if r["plain_over_tress"] >= 20 else "NOT met"
        print(f"plain Python / tress.load = {r['plain_over_tress']:.1f} (target >= 20: {ok})")
    if args.json:
        args.json.write_text(json.dumps(r, indent=2) + "\n")


if __name__ == "__main__":
    main()
