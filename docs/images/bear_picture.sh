#!/usr/bin/env bash
# Renders the README's bear picture: scenes/bear.toml (962k fur strands) at 640x360 as strands,
# as the volume with the default settings, and as the volume with the paper's counting, each
# cropped to the hair and placed side by side (docs/images/bear-strands-volume.png).
# Needs a built tress (TRESS, default target/release/tress) and python3 with Pillow and numpy.
set -euo pipefail
TRESS=${TRESS:-target/release/tress}
out=$(mktemp -d)
common=(scenes/bear.toml --width 640 --height 360)
"$TRESS" render "${common[@]}" -o "$out/strands.png"
"$TRESS" render "${common[@]}" --technique volume -o "$out/volume.png"
"$TRESS" render "${common[@]}" --technique volume --set 'volume.occlusion="strands"' \
    --set 'volume.opacity="iso"' --set volume.iso=2 --set volume.ao=true -o "$out/paper.png"
python3 - "$out" <<'PY'
import sys
import numpy as np
from PIL import Image
d = sys.argv[1]
names = ("strands", "volume", "paper")
panels = [np.asarray(Image.open(f"{d}/{n}.png").convert("RGB")) for n in names]
# The box of every pixel that is not the background (the top-left pixel), grown by 8.
busy = np.zeros(panels[0].shape[:2], bool)
for p in panels:
    busy |= np.abs(p.astype(int) - p[0, 0].astype(int)).max(-1) > 2
ys, xs = np.nonzero(busy)
y0, y1 = max(ys.min() - 8, 0), min(ys.max() + 9, busy.shape[0])
x0, x1 = max(xs.min() - 8, 0), min(xs.max() + 9, busy.shape[1])
crops = [p[y0:y1, x0:x1] for p in panels]
Image.fromarray(np.concatenate(crops, axis=1)).save(
    "docs/images/bear-strands-volume.png", optimize=True)
PY
rm -r "$out"
echo "wrote docs/images/bear-strands-volume.png"
