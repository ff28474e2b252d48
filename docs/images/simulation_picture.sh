#!/usr/bin/env bash
# Renders the README's simulation contact sheet: scenes/simulate.toml (the demo ponytail,
# simulated on the GPU, the head turning 60° each way every 2 s) for 48 frames at 24 fps
# (2 s) at 480x270, and lays frames 0, 6, 12, ..., 42 (every quarter second) out 4 x 2 into
# docs/images/simulation-turn.png, each labelled with its time. Prints the frames' simulation
# figures. Needs a built tress (TRESS, default target/release/tress) and python3 with Pillow.
set -euo pipefail
TRESS=${TRESS:-target/release/tress}
out=$(mktemp -d)
"$TRESS" render scenes/simulate.toml --frames 48 --width 480 --height 270 \
  -o "$out/turn.png" --json > "$out/turn.json"
python3 - "$out" <<'PY'
import json, sys
from PIL import Image, ImageDraw
d = sys.argv[1]
picks = list(range(0, 48, 6))
w, h = 480, 270
sheet = Image.new("RGB", (4 * w, 2 * h))
for n, k in enumerate(picks):
    im = Image.open(f"{d}/turn-{k:04d}.png").convert("RGB")
    ImageDraw.Draw(im).text((8, 6), f"t = {k / 24:.2f} s", fill=(235, 235, 235))
    sheet.paste(im, ((n % 4) * w, (n // 4) * h))
sheet.save("docs/images/simulation-turn.png", optimize=True)
sim = json.load(open(f"{d}/turn.json"))["simulation"]
ms = [f["wall_ms"] for f in sim if f.get("wall_ms") is not None and f["steps"] > 0]
print(f"{sim[0]['guides']} guides of {sim[0]['strands']} strands, "
      f"{sum(f['steps'] for f in sim)} steps, {sum(ms) / len(ms):.1f} ms a frame simulating, "
      f"{sim[0]['bytes'] / 2**20:.1f} MiB")
PY
