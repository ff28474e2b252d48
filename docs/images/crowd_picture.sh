#!/usr/bin/env bash
# Renders the README's crowd picture: scenes/crowd.toml (six generated characters, technique
# "auto") at 1280x720, scaled to 960x540 (docs/images/crowd.png), and prints what drew each one.
# Needs a built tress (TRESS, default target/release/tress) and python3 with Pillow.
set -euo pipefail
TRESS=${TRESS:-target/release/tress}
out=$(mktemp -d)
"$TRESS" render scenes/crowd.toml -o "$out/crowd.png" --json > "$out/crowd.json"
python3 - "$out" <<'PY'
import json, sys
from PIL import Image
d = sys.argv[1]
Image.open(f"{d}/crowd.png").convert("RGB").resize((960, 540), Image.LANCZOS).save(
    "docs/images/crowd.png", optimize=True)
for i, o in enumerate(json.load(open(f"{d}/crowd.json"))["objects"]):
    print(f"hair {i}: {o['technique']}, lod {o['lod']:.3f}, {o['size_px']:.0f} px")
PY
