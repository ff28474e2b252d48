"""Grooms per minute through ``tress.render_dataset``, for each engine and worker count.

Generated grooms (``--grooms`` 8 of ``--strands`` 20,000, styles in turn) are saved as .hair in a
temporary folder and rendered from ``--views`` 16 orbit cameras at ``--size`` 256 × 256 with
maps rgb + alpha, once per configuration (``--configs local:1,local:2,dask:2``: engine:workers),
each into a fresh folder. The time is render_dataset's whole call: starting the worker processes
(and for Dask the LocalCluster), opening one GPU device per worker, loading, rendering, writing.

    python crates/tress-py/bench/bench_dataset.py --json dataset.json
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import tempfile

import tress

STYLES = ("straight", "wavy", "curly", "ponytail")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grooms", type=int, default=8)
    ap.add_argument("--strands", type=int, default=20_000)
    ap.add_argument("--views", type=int, default=16)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--configs", default="local:1,local:2,dask:1,dask:2")
    ap.add_argument("--build", default="unspecified", help="the package's build, for the record")
    ap.add_argument("--json", type=pathlib.Path)
    args = ap.parse_args()

    cams = tress.orbit(args.views, radius=60, elevation=10, target=(0, -5, 0), width=args.size,
                       height=args.size)
    result = {"grooms": args.grooms, "strands": args.strands, "views": args.views, "size": args.size,
              "maps": ["rgb", "alpha"], "build": args.build, "cpus": os.cpu_count(),
              "python": platform.python_version(), "runs": []}
    with tempfile.TemporaryDirectory() as tmp:
        inputs = []
        for i in range(args.grooms):
            style = STYLES[i % len(STYLES)]
            p = os.path.join(tmp, f"{i:02d}_{style}.hair")
            tress.save(p, tress.generate(style, strands=args.strands, seed=i))
            inputs.append(p)
        adapter = tress.Renderer().adapter
        result["adapter"] = adapter
        print(f"{args.grooms} grooms x {args.strands:,} strands, {args.views} views at "
              f"{args.size}x{args.size}, rgb+alpha, on {adapter}; build: {args.build}")
        print(f"{'engine':8} {'workers':>7} {'seconds':>9} {'grooms/min':>11} {'frames/s':>9}")
        for config in args.configs.split(","):
            engine, workers = config.split(":")
            out = os.path.join(tmp, f"out_{engine}_{workers}")
            s = tress.render_dataset(inputs, cams, out, maps=("rgb", "alpha"), engine=engine,
                                     workers=int(workers), progress=False, png=False)
            if s["failed"] or s["done"] != args.grooms:
                raise SystemExit(f"{config}: {s}")
            gpm = s["done"] / s["seconds"] * 60
            fps = s["done"] * args.views / s["seconds"]
            print(f"{engine:8} {workers:>7} {s['seconds']:9.1f} {gpm:11.2f} {fps:9.2f}")
            result["runs"].append({"engine": engine, "workers": int(workers), "seconds": s["seconds"],
                                   "grooms_per_minute": gpm, "frames_per_second": fps})
    if args.json:
        args.json.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
