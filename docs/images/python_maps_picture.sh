#!/usr/bin/env bash
# The README's Python figure: the worked example's maps of a generated groom, two of its 16 views
# (front, and 90 degrees round): shaded frame, HairStep strand map, NeuralHaircut orientation
# (degrees as uint8) and hair mask. Needs the package (`pip install ./crates/tress-py`) and Pillow.
set -euo pipefail
cd "$(dirname "$0")/../.."
PY="${PYTHON:-python3}"
out=$(mktemp -d)
"$PY" crates/tress-py/examples/strand_maps.py "$out" --strands 20000 --size 256
"$PY" - "$out" docs/images/python-maps.png <<'PYEOF'
import sys
from PIL import Image
src, dst = sys.argv[1], sys.argv[2]
kinds = ["rgb", "strand_map", "orientation", "mask"]
ims = [Image.open(f"{src}/{v:02d}_{k}.png").convert("RGB") for v in (0, 4) for k in kinds]
w, h = ims[0].size
sheet = Image.new("RGB", (w * 4, h * 2))
for i, im in enumerate(ims):
    sheet.paste(im, ((i % 4) * w, (i // 4) * h))
sheet.save(dst, optimize=True)
PYEOF
echo "wrote docs/images/python-maps.png"
