#!/usr/bin/env bash
# Renders the README's picture: the hybrid paper's 136,320-strand ponytail (scenes/ponytail.toml's
# generator, 13 vertices a strand) on the generated head, close, from behind the right ear, with
# the strand rasterizer under Marschner shading (strands.shading = "marschner") and ADSM
# self-shadowing, lit by a warm key light above and a cool rim light from the front
# (docs/images/portrait.png, 1280x720). On lavapipe with 2 busy CPU cores the run took 15 minutes,
# the frame 6.5 of them (93M fragments through ShortCut; its shading pass 5.5 minutes).
# Needs a built tress (TRESS, default target/release/tress). Extra arguments go to tress render
# (e.g. --width 480 --height 270 --set hair.0.strand_ratio=0.25 for a quick look).
set -euo pipefail
TRESS=${TRESS:-target/release/tress}
OUT=${OUT:-docs/images/portrait.png}
scene=$(mktemp --suffix .toml)
trap 'rm -f "$scene"' EXIT
cat > "$scene" <<'TOML'
technique = "strands"
background = [0.045, 0.05, 0.062]

[camera]                          # close, from behind the right ear, a little above
eye = [38.0, 15.0, -20.0]
target = [1.0, 1.8, -5.0]
up = [0.0, 1.0, 0.0]
fov_y_deg = 33.0
near = 1.0
far = 500.0

[[light]]                         # warm key, high behind the camera: the crown's highlight bands
direction = [0.5, 0.75, -0.45]
color = [1.0, 0.93, 0.84]
intensity = 2.0

[[light]]                         # cool rim from the front left: light through the silhouette
direction = [-0.6, 0.35, 0.7]
color = [0.75, 0.85, 1.0]
intensity = 1.2

[[hair]]                          # the ponytail of Jansson et al. 2019, Table 1
generator = { style = "ponytail", strands = 136320, vertices = 13, length = 35.0, seed = 1 }

[hair.material]                   # a light-brown fibre: melanin gives the colour, TRT the glint
base_color = [0.32, 0.2, 0.11]
eumelanin = 0.35
pheomelanin = 0.25
beta_m = 0.25
beta_n = 0.3

[head]
generated = true

[strands]
shading = "marschner"
width_px = 1.0                    # finer than the default 1.5 at this distance
shadow_map_size = 2048

[output]
width = 1280
height = 720
TOML
"$TRESS" render "$scene" -o "$OUT" "$@"
echo "wrote $OUT"
