#!/usr/bin/env bash
# Renders the README's first picture: the built-in demo with the strand rasterizer, the same view
# with the volume raymarcher, and a close-up of the strands, side by side (docs/images/first.png).
# Needs a built tress (TRESS, default target/release/tress) and python3 with Pillow.
set -euo pipefail
TRESS=${TRESS:-target/release/tress}
out=$(mktemp -d)
common=(--width 640 --height 360)
"$TRESS" render "${common[@]}" -o "$out/strands.png"
"$TRESS" render "${common[@]}" --set 'technique="volume"' -o "$out/volume.png"
"$TRESS" render "${common[@]}" --set 'camera.eye=[30.0,12.0,-26.0]' \
    --set 'camera.target=[1.0,0.0,-6.0]' -o "$out/close.png"
python3 - "$out" <<'PY'
import sys
from PIL import Image
d = sys.argv[1]
panels = [Image.open(f"{d}/{n}.png") for n in ("strands", "volume", "close")]
w, h = panels[0].size
strip = Image.new("RGB", (3 * w, h))
for i, p in enumerate(panels):
    strip.paste(p, (i * w, 0))
strip.save("docs/images/first.png", optimize=True)
PY
rm -r "$out"
echo "wrote docs/images/first.png"
