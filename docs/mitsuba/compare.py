#!/usr/bin/env python3
"""Render a tress scene with Mitsuba 3 and with `tress reference`, and compare the two.

The check of tress's physically based reference (`strands.shading = "marschner"`, Chiang et
al. 2016's hair BSDF in `tress-trace`) against an outside renderer: Mitsuba 3's `hair` BSDF on
curve shapes, CPU variant `scalar_rgb` (PyPI `mitsuba`, tested with 3.9.1).

    pip install mitsuba numpy pillow
    python3 docs/mitsuba/compare.py docs/mitsuba/blond.toml --tress target/release/tress

The committed images and figures, and the command that made them: docs/mitsuba/README.md.

For each scene `NAME.toml` this writes, into `--out` (default: the scene's folder):

- `NAME-mitsuba.png`: Mitsuba's image (8-bit sRGB, as tress writes PNGs), the file the Rust
  test `crates/tress-cli/tests/cli_mitsuba.rs` compares tress's tracer against;
- `NAME-tress.png`: `tress reference` at `--tress-spp` samples;
- `NAME-flip.png`: FLIP's per-pixel error of the tress image against Mitsuba's;
- `NAME-report.json`: both renders' settings and times, mean FLIP over the frame and over the
  hair's pixels (`tress compare-images --mask`).

The Mitsuba scene (`NAME.xml` and the curves `NAME-curves.txt`) is written to `--work` (default:
a temporary folder) and can be kept and rendered with `mitsuba NAME.xml`.

How the tress scene maps to Mitsuba (every convention read from tress-trace's
`tracer/path.rs`, `tracer/setup.rs` and `tress_shading::fiber`):

- Hair: the scene's one `[[hair]]` generator is run through `tress generate` with the same
  parameters (the scene loader calls the same generator), the `.hair` file is read here, and
  every strand becomes one curve with radius `thickness / 2` per control point (`[hair.material]
  thickness` if given, else the file's per-vertex thickness). tress traces each strand as a
  chain of capsules (a polyline tube). Mitsuba gets a `bsplinecurve` (`--curve`, the default)
  through the strand's vertices (`bspline_controls`): the shape Mitsuba's `hair` BSDF is written
  for, whose shading frame has the fibre's tangent as local `y`, which the BSDF takes as the
  fibre axis. The curve rounds the polyline's corners (the report's `curve_deviation`, the
  largest distance at a segment's midpoint, is 0.09 world units for the committed scenes, a
  third of a pixel). `--curve linearcurve` takes the polyline as it is, but Mitsuba 3.9.1's
  `linearcurve` builds its shading frame from the normal alone, so the BSDF sees an arbitrary
  direction perpendicular to the normal as the fibre axis (speckled, wrong highlights: mean
  FLIP 0.14 against tress at 16 spp, measured before tress's ray-origin fix; `bsplinecurve`
  gave 0.04 with direct light only at 128 spp).
- Camera: tress's `fov_y_deg` is the vertical field of view; Mitsuba's `fov_axis = "y"`, the
  same `lookat`, a box reconstruction filter (tress averages the samples inside each pixel).
- Lights: a tress light's `color * intensity` is the radiance a white Lambertian surface facing
  it reflects, so its irradiance is `E = pi * color * intensity`; Mitsuba's `directional`
  emitter takes that irradiance and the direction light travels (minus tress's `direction`,
  which points towards the light).
- Environment: tress's path tracer sees a uniform sky of radiance `trace.ambient` on every ray
  after the first, and the scene's `background` on camera rays. Mitsuba gets a `constant`
  emitter of radiance `ambient`, hidden from camera rays (`hide_emitters`), and its RGBA image
  is composited over `background` (`rgb + (1 - alpha) * background`).
- Fibre: melanin is given to Mitsuba as melanin (both use d'Eon et al. 2011's coefficients,
  eumelanin (0.419, 0.697, 1.37) and pheomelanin (0.187, 0.4, 1.05) per fibre radius);
  `sigma_a` and `target_color` (through Chiang's mapping, computed here as tress does) are
  given as `sigma_a`, which Mitsuba also applies per fibre radius. `beta_m`, `beta_n` are
  Mitsuba's `longitudinal_roughness`, `azimuthal_roughness`; `alpha_deg` its `scale_tilt`
  (degrees in both); `eta` its `int_ior` with `ext_ior = 1` (Mitsuba's default exterior is air,
  1.000277).
- Paths: tress's `trace.bounces = B` bounces after the camera ray's hit, with next-event
  estimation at each of the B + 1 vertices, is Mitsuba's `path` integrator with
  `max_depth = B + 2` (Mitsuba counts the camera segment and the light segment). With tress's
  default B = 32 the one place they differ, the sky seen after the last bounce, is far below the
  noise. Both play Russian roulette, which is unbiased.

Only what this mapping covers is accepted: one generated `[[hair]]` entry without follow hairs,
`strand_ratio` or transform, no head (`[head] generated = false`), `strands.shading =
"marschner"`. Anything else is an error.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

# d'Eon et al. 2011's melanin absorption per fibre radius (tress_shading::fiber, Mitsuba's hair).
EUMELANIN_SIGMA_A = np.array([0.419, 0.697, 1.37])
PHEOMELANIN_SIGMA_A = np.array([0.187, 0.4, 1.05])

# tress's scene defaults (crates/tress-scene/doc/defaults.toml) used when a key is absent.
CAMERA_DEFAULTS = {
    "eye": [32.0, 4.0, 76.0],
    "target": [0.0, -10.0, 0.0],
    "up": [0.0, 1.0, 0.0],
    "fov_y_deg": 35.0,
    "near": 1.0,
    "far": 500.0,
}
FIBER_DEFAULTS = {"beta_m": 0.3, "beta_n": 0.3, "alpha_deg": 2.0, "eta": 1.55}
TRACE_BOUNCES = 32


def fail(msg: str) -> None:
    sys.exit(f"compare.py: {msg}")


# --- tress scene ------------------------------------------------------------------------------


def read_scene(path: Path) -> dict:
    with open(path, "rb") as f:
        scene = tomllib.load(f)
    strands = scene.get("strands", {})
    if strands.get("shading") != "marschner":
        fail(f'{path}: needs [strands] shading = "marschner" (the physically based tracer)')
    head = scene.get("head", {})
    if head.get("generated", True) or "obj" in head or "mesh" in head:
        fail(f"{path}: needs [head] generated = false (Mitsuba gets no head)")
    hair = scene.get("hair", [])
    if len(hair) != 1 or "generator" not in hair[0] or hair[0].get("files"):
        fail(f"{path}: needs exactly one [[hair]] entry with a generator")
    for key in ("follow", "transform"):
        if key in hair[0]:
            fail(f"{path}: [[hair]] {key} is not translated")
    if hair[0].get("strand_ratio", 1.0) != 1.0:
        fail(f"{path}: [[hair]] strand_ratio is not translated")
    if "light" not in scene:
        fail(f"{path}: give the [[light]] entries explicitly")
    return scene


def fiber(material: dict) -> dict:
    """Mitsuba `hair` parameters for a `[hair.material]` (tress_scene::Material::fiber)."""
    f = {k: material.get(k, v) for k, v in FIBER_DEFAULTS.items()}
    melanin = "eumelanin" in material or "pheomelanin" in material
    given = [melanin, "sigma_a" in material, "target_color" in material]
    if sum(given) > 1:
        fail("give one of melanin, sigma_a or target_color")
    out = {
        "longitudinal_roughness": f["beta_m"],
        "azimuthal_roughness": f["beta_n"],
        "scale_tilt": f["alpha_deg"],
        "int_ior": f["eta"],
        "ext_ior": 1.0,
    }
    if "sigma_a" in material:
        out["sigma_a"] = list(map(float, material["sigma_a"]))
    elif "target_color" in material:
        b = f["beta_n"]
        d = 5.969 - 0.215 * b + 2.532 * b**2 - 10.73 * b**3 + 5.574 * b**4 + 0.245 * b**5
        out["sigma_a"] = [(math.log(c) / d) ** 2 for c in material["target_color"]]
    else:
        out["eumelanin"] = float(material.get("eumelanin", 1.3))
        out["pheomelanin"] = float(material.get("pheomelanin", 0.2))
    return out


def generate_hair(tress: str, hair: dict, work: Path) -> Path:
    """The scene's generated hair as a `.hair` file, through `tress generate`."""
    g = dict(hair["generator"])
    out = work / "hair.hair"
    cmd = [tress, "generate", g.pop("style"), "-o", str(out)]
    for key, value in g.items():
        cmd += [f"--{key.replace('_', '-')}", str(value)]
    subprocess.run(cmd, check=True, capture_output=True)
    return out


def read_hair(path: Path) -> tuple[list[int], np.ndarray, np.ndarray | None]:
    """Cem Yuksel's `.hair` (crates/tress-hair/src/formats/hair.rs): vertices per strand,
    points (N x 3) and per-point thickness (or None)."""
    data = path.read_bytes()
    magic, hairs, points, flags, default_segments = struct.unpack_from("<4s4I", data, 0)
    default_thickness = struct.unpack_from("<f", data, 20)[0]
    if magic != b"HAIR":
        fail(f"{path}: not a .hair file")
    at = 128
    if flags & 1:
        segments = np.frombuffer(data, "<u2", hairs, at).astype(int)
        at += 2 * hairs
    else:
        segments = np.full(hairs, default_segments)
    if not flags & 2:
        fail(f"{path}: no points")
    pos = np.frombuffer(data, "<f4", 3 * points, at).reshape(points, 3)
    at += 12 * points
    thickness = None
    if flags & 4:
        thickness = np.frombuffer(data, "<f4", points, at)
    elif default_thickness > 0 and default_thickness != 1.0:
        thickness = np.full(points, default_thickness)
    counts = [int(s) + 1 for s in segments]
    if sum(counts) != points:
        fail(f"{path}: segment counts do not add up to the point count")
    return counts, pos, thickness


# --- Mitsuba scene ----------------------------------------------------------------------------


def bspline_controls(v: np.ndarray) -> np.ndarray:
    """Control points of the uniform cubic B-spline that passes through the polyline's vertices
    `v` (n x k, n >= 2): n + 2 points `P` with `(P[i] + 4 P[i+1] + P[i+2]) / 6 = v[i]` and zero
    second difference at both ends, so the curve starts at the root and ends at the tip."""
    n = len(v)
    a = np.zeros((n + 2, n + 2))
    for i in range(n):
        a[i, i : i + 3] = [1 / 6, 4 / 6, 1 / 6]
    a[n, 0:3] = [1, -2, 1]
    a[n + 1, n - 1 : n + 2] = [1, -2, 1]
    rhs = np.vstack([v, np.zeros((2, v.shape[1]))])
    return np.linalg.solve(a, rhs)


def write_curves(path: Path, counts, pos, radius, kind: str) -> float:
    """Mitsuba's curve file: `x y z radius` per control point, a blank line between curves.
    `linearcurve` takes the polyline as it is; `bsplinecurve` the control points of the B-spline
    through its vertices (see `bspline_controls`). Returns the largest distance between the
    B-spline and the polyline at the segments' midpoints (0 for `linearcurve`)."""
    lines = []
    start = 0
    deviation = 0.0
    for n in counts:
        v = np.hstack([pos[start : start + n], radius[start : start + n, None]])
        if kind == "bsplinecurve":
            p = bspline_controls(v)
            mid = (p[:-3] + 23 * p[1:-2] + 23 * p[2:-1] + p[3:]) / 48  # B-spline at t = 1/2
            poly = 0.5 * (v[:-1] + v[1:])
            deviation = max(deviation, float(np.linalg.norm(mid[:, :3] - poly[:, :3], axis=1).max()))
            v = p
        for x, y, z, r in v:
            lines.append(f"{x:.7g} {y:.7g} {z:.7g} {r:.7g}")
        lines.append("")
        start += n
    path.write_text("\n".join(lines))
    return deviation


def v3(v) -> str:
    return ", ".join(f"{float(x):.9g}" for x in v)


def mitsuba_xml(scene: dict, curves: Path, curve: str, bsdf: dict, spp: int, ambient: float,
                bounces: int):
    cam = {k: scene.get("camera", {}).get(k, v) for k, v in CAMERA_DEFAULTS.items()}
    out = scene.get("output", {})
    width, height = out.get("width", 1280), out.get("height", 720)
    emitters = []
    for light in scene["light"]:
        d = np.array(light.get("direction", [0.0, 1.0, 1.0]), float)
        d /= np.linalg.norm(d)
        e = math.pi * np.array(light.get("color", [1.0, 1.0, 1.0])) * light.get("intensity", 1.0)
        emitters.append(
            f'    <emitter type="directional">\n'
            f'        <vector name="direction" value="{v3(-d)}"/>\n'
            f'        <rgb name="irradiance" value="{v3(e)}"/>\n'
            f"    </emitter>"
        )
    params = []
    for key, value in bsdf.items():
        if isinstance(value, list):
            params.append(f'        <rgb name="{key}" value="{v3(value)}"/>')
        else:
            params.append(f'        <float name="{key}" value="{value:.9g}"/>')
    nl = "\n"
    return f"""<scene version="3.0.0">
    <integrator type="path">
        <integer name="max_depth" value="{bounces + 2}"/>
        <boolean name="hide_emitters" value="true"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="{cam['fov_y_deg']}"/>
        <string name="fov_axis" value="y"/>
        <float name="near_clip" value="{cam['near']}"/>
        <float name="far_clip" value="{cam['far']}"/>
        <transform name="to_world">
            <lookat origin="{v3(cam['eye'])}" target="{v3(cam['target'])}" up="{v3(cam['up'])}"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="{spp}"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="{width}"/>
            <integer name="height" value="{height}"/>
            <string name="pixel_format" value="rgba"/>
            <rfilter type="box"/>
        </film>
    </sensor>
{nl.join(emitters)}
    <emitter type="constant">
        <rgb name="radiance" value="{v3([ambient] * 3)}"/>
    </emitter>
    <shape type="{curve}">
        <string name="filename" value="{curves.name}"/>
        <bsdf type="hair">
{nl.join(params)}
        </bsdf>
    </shape>
</scene>
"""


def linear_to_srgb8(rgb: np.ndarray) -> np.ndarray:
    """tress_trace::image: clamp, sRGB-encode, round to 8 bits."""
    c = np.clip(rgb, 0.0, 1.0)
    s = np.where(c <= 0.0031308, c * 12.92, 1.055 * np.power(c, 1 / 2.4) - 0.055)
    return (s * 255.0 + 0.5).astype(np.uint8)


def write_png(path: Path, rgb8: np.ndarray) -> None:
    import mitsuba as mi

    mi.Bitmap(rgb8, mi.Bitmap.PixelFormat.RGB).write(str(path))


def render_pass(xml: str, seed: int, spp: int, out: str) -> None:
    """One pass of Mitsuba's RGBA image, saved as `.npy` (run in its own process)."""
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    scene = mi.load_file(xml)
    np.save(out, np.array(mi.render(scene, seed=seed, spp=spp), np.float32))


def render_mitsuba(xml: Path, background, spp: int, seed: int, pass_spp: int) -> np.ndarray:
    """Mitsuba's image composited over `background`: the mean of passes of `pass_spp` samples,
    pass `k` with seed `seed * 65536 + k`, each in its own process. Mitsuba 3.9.1's scalar
    variant crashed (segmentation fault) now and then on these scenes, after a few hundred
    samples; a pass that crashes is run again with the next unused seed."""
    passes = max(1, -(-spp // pass_spp))
    rgba = 0.0
    next_seed = seed * 65536 + passes
    for k in range(passes):
        n = min(pass_spp, spp - k * pass_spp)
        out = xml.parent / f"pass-{k}.npy"
        pass_seed = seed * 65536 + k
        for _ in range(5):
            run = subprocess.run([sys.executable, __file__, "--render-pass", str(xml),
                                  str(pass_seed), str(n), str(out)])
            if run.returncode == 0:
                break
            print(f"Mitsuba pass {k} (seed {pass_seed}) failed ({run.returncode}); "
                  f"again with seed {next_seed}", file=sys.stderr)
            pass_seed, next_seed = next_seed, next_seed + 1
        else:
            fail("Mitsuba failed five times on one pass")
        rgba = rgba + n * np.load(out).astype(np.float64)
        out.unlink()
    rgba /= spp
    alpha = rgba[..., 3:4]
    return rgba[..., :3] + (1.0 - alpha) * np.array(background)


# --- main -------------------------------------------------------------------------------------


def main() -> None:
    if len(sys.argv) == 6 and sys.argv[1] == "--render-pass":
        render_pass(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5])
        return
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="+", type=Path, help="tress scene files (.toml)")
    ap.add_argument("--tress", default="tress", help="the tress binary (default: on PATH)")
    ap.add_argument("--spp", type=int, default=1024, help="Mitsuba samples per pixel")
    ap.add_argument("--pass-spp", type=int, default=64, help="Mitsuba samples per render pass")
    ap.add_argument("--tress-spp", type=int, default=1024, help="tress samples per pixel")
    ap.add_argument("--bounces", type=int, default=TRACE_BOUNCES, help="trace.bounces")
    ap.add_argument("--ambient", type=float, default=0.08,
                    help="trace.ambient, the sky's radiance (default 0.08, tress's)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--curve", choices=["bsplinecurve", "linearcurve"], default="bsplinecurve",
                    help="Mitsuba shape for the strands (see the module docs)")
    ap.add_argument("--out", type=Path, default=None, help="output folder (default: the scene's)")
    ap.add_argument("--work", type=Path, default=None,
                    help="keep the Mitsuba scene and scratch files here")
    ap.add_argument("--skip-mitsuba", action="store_true",
                    help="reuse NAME-mitsuba.png from --out; only render tress and compare")
    args = ap.parse_args()

    for path in args.scenes:
        scene = read_scene(path)
        name = path.stem
        out = args.out or path.parent
        out.mkdir(parents=True, exist_ok=True)
        work = args.work or Path(tempfile.mkdtemp(prefix="tress-mitsuba-"))
        work.mkdir(parents=True, exist_ok=True)
        ambient = args.ambient
        background = scene.get("background", [0.2, 0.2, 0.2])
        report = {"scene": str(path), "bounces": args.bounces, "ambient": ambient,
                  "background": background}

        mitsuba_png = out / f"{name}-mitsuba.png"
        if not args.skip_mitsuba:
            import mitsuba as mi

            material = scene["hair"][0].get("material", {})
            counts, pos, thickness = read_hair(generate_hair(args.tress, scene["hair"][0], work))
            if "thickness" in material:
                thickness = np.full(len(pos), float(material["thickness"]))
            if thickness is None:
                fail(f"{path}: the hair has no thickness; set [hair.material] thickness")
            curves = work / f"{name}-curves.txt"
            deviation = write_curves(curves, counts, pos, 0.5 * thickness, args.curve)
            bsdf = fiber(material)
            xml = work / f"{name}.xml"
            xml.write_text(mitsuba_xml(scene, curves, args.curve, bsdf, args.spp, ambient,
                                       args.bounces))
            start = time.time()
            rgb = render_mitsuba(xml, background, args.spp, args.seed, args.pass_spp)
            seconds = time.time() - start
            write_png(mitsuba_png, linear_to_srgb8(rgb))
            mi.Bitmap(rgb.astype(np.float32)).write(str(work / f"{name}-mitsuba.exr"))
            report["mitsuba"] = {
                "version": mi.__version__, "variant": "scalar_rgb", "spp": args.spp,
                "seconds": round(seconds, 1), "strands": len(counts), "bsdf": bsdf,
                "threads": os.cpu_count(), "curve": args.curve,
                "curve_deviation": round(deviation, 6),
            }
            print(f"{name}: Mitsuba {args.spp} spp in {seconds:.0f} s", file=sys.stderr)

        tress_png = out / f"{name}-tress.png"
        cmd = [args.tress, "reference", str(path), "-o", str(tress_png),
               "--spp", str(args.tress_spp), "--seed", str(args.seed), "--json",
               "--set", f"trace.ambient={ambient}", "--set", f"trace.bounces={args.bounces}"]
        start = time.time()
        run = subprocess.run(cmd, check=True, capture_output=True, text=True)
        seconds = time.time() - start
        report["tress"] = {"spp": args.tress_spp, "seconds": round(seconds, 1),
                           "command": " ".join(cmd[1:]), **json.loads(run.stdout)}
        print(f"{name}: tress {args.tress_spp} spp in {seconds:.0f} s", file=sys.stderr)

        # The hair's pixels: those where either image differs from the background.
        from PIL import Image

        a = np.asarray(Image.open(mitsuba_png).convert("RGB")).astype(int)
        b = np.asarray(Image.open(tress_png).convert("RGB")).astype(int)
        bg8 = linear_to_srgb8(np.array(background)).astype(int)
        hair = (np.abs(a - bg8).max(-1) > 1) | (np.abs(b - bg8).max(-1) > 1)
        mask = work / f"{name}-mask.png"
        Image.fromarray((hair * 255).astype(np.uint8)).save(mask)
        flip = subprocess.run(
            [args.tress, "compare-images", str(mitsuba_png), str(tress_png), "--json",
             "--mask", str(mask), "--heatmap", str(out / f"{name}-flip.png")],
            check=True, capture_output=True, text=True)
        scores = json.loads(flip.stdout)
        report["compare"] = {**scores, "hair_share": round(float(hair.mean()), 4)}
        (out / f"{name}-report.json").write_text(json.dumps(report, indent=2) + "\n")
        print(json.dumps({"scene": name, **report["compare"]}))
        if args.work is None:
            shutil.rmtree(work)


if __name__ == "__main__":
    main()
