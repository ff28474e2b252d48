#!/usr/bin/env bash
# Issue 36's decomposition: where the strands' Marschner frame departs from the path tracer, one
# cause at a time. Each step turns on one more part of the light transport in both the tracer
# (`tress reference`) and the strand rasterizer (`tress render`), and scores the pair over the
# hair at the matched scale (3x3 boxes in linear light) with its mean colour ratio:
#
#   A  lights only         single scattering, unshadowed, no ambient light
#                          ambient=0 trace.shadows=false trace.bounces=0 /
#                          ambient=0 strands.shadows=false strands.multiple_scattering=false
#   B  + shadows           ambient=0 trace.bounces=0 / ambient=0 strands.multiple_scattering=false
#   C  + multiple          ambient=0 (every bounce; the strands' dual scattering)
#      scattering
#   D  + ambient light     the full frame (defaults)
#   W  width               step A with the tracer's strands as wide as the GPU's lines
#                          (trace.width=screen: `width_px` and `thickness_fade` as the GPU draws)
#
# The tracer's fibres are opaque (their light transport is Chiang's BSDF), the rasterizer's lines
# have `strands.alpha` and coverage. AO is off in both (trace.ao_samples=0; the strands' `ao` is
# off by default). Usage: run.sh OUT_DIR [SCENE] [SPP] (defaults: the demo at 384x216, 128 spp).
# Writes OUT_DIR/decomposition.md. About 6 minutes on lavapipe and 2 cores.
set -euo pipefail
out=${1:?usage: run.sh OUT_DIR [SCENE] [SPP]}
scene=${2:-scenes/demo.toml}
spp=${3:-128}
tress=${TRESS:-target/release/tress}
mkdir -p "$out"
size=(--width 384 --height 216)
marschner=(--set 'strands.shading="marschner"')
trace() { # name, tracer settings...
    local name=$1; shift
    "$tress" reference "$scene" "${size[@]}" "${marschner[@]}" --spp "$spp" \
        --set trace.ao_samples=0 "$@" -o "$out/$name-reference.png" > /dev/null
}
raster() { # name, strand settings...
    local name=$1; shift
    "$tress" render "$scene" "${size[@]}" "${marschner[@]}" "$@" -o "$out/$name-strands.png" \
        > /dev/null
}
# The hair's pixels: where the frame with hair differs from the one without (no shadows either).
raster bare --set strands.alpha=0 --set strands.shadows=false
raster A --set ambient=0 --set strands.shadows=false --set strands.multiple_scattering=false
raster B --set ambient=0 --set strands.multiple_scattering=false
raster C --set ambient=0
raster D
trace A --set ambient=0 --set trace.shadows=false --set trace.bounces=0
trace W --set ambient=0 --set trace.shadows=false --set trace.bounces=0 --set trace.width=screen
trace B --set ambient=0 --set trace.bounces=0
trace C --set ambient=0
trace D
python3 - "$out" "$tress" <<'PY'
import json, subprocess, sys
from PIL import Image, ImageChops
out, tress = sys.argv[1], sys.argv[2]
mask = ImageChops.difference(Image.open(f"{out}/D-strands.png").convert("RGB"),
                             Image.open(f"{out}/bare-strands.png").convert("RGB"))
mask = mask.point(lambda v: 255 if v > 1 else 0).convert("L")
Image.merge("RGB", [mask] * 3).save(f"{out}/mask.png")
def score(ref, test):
    r = subprocess.run([tress, "compare-images", ref, test, "--mask", f"{out}/mask.png", "--json"],
                       check=True, capture_output=True, text=True)
    return json.loads(r.stdout)
rows = [("A", "lights only (single scattering, unshadowed, no ambient)", "A-reference", "A-strands"),
        ("W", "A, the tracer's strands as wide as the GPU's lines", "W-reference", "A-strands"),
        ("B", "+ shadows", "B-reference", "B-strands"),
        ("C", "+ multiple scattering", "C-reference", "C-strands"),
        ("D", "+ ambient light (the full frame)", "D-reference", "D-strands"),
        ("W/A", "the GPU's width in the tracer (tracer W / A)", "A-reference", "W-reference"),
        ("B/A", "what shadows keep (tracer B / A)", "A-reference", "B-reference"),
        ("B/A", "what shadows keep (strands B / A)", "A-strands", "B-strands"),
        ("C/B", "what multiple scattering adds (tracer C / B)", "B-reference", "C-reference"),
        ("C/B", "what multiple scattering adds (strands C / B)", "B-strands", "C-strands"),
        ("D/C", "what ambient light adds (tracer D / C)", "C-reference", "D-reference"),
        ("D/C", "what ambient light adds (strands D / C)", "C-strands", "D-strands")]
lines = ["| step | what | FLIP over the hair, scale 3 | colour ratio (R / G / B) |",
         "| --- | --- | ---: | --- |"]
for step, what, ref, test in rows:
    m = score(f"{out}/{ref}.png", f"{out}/{test}.png")["matched"]
    ratio = " / ".join(f"{c:.3f}" for c in m["color_ratio"])
    lines.append(f"| {step} | {what} | {m['flip_masked']:.3f} | {ratio} |")
open(f"{out}/decomposition.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
