"""Training maps for hair reconstruction from a generated groom, 16 views around it:
HairStep-style strand maps and depth, NeuralHaircut-style orientation PNGs (degrees in
[0, 180) as uint8) with their masks, and the shaded frames.

    python crates/tress-py/examples/strand_maps.py OUT_DIR [--strands N] [--size PX]
"""

import argparse
import pathlib
import time

import numpy as np

import tress


def save_png(path, array):
    """uint8 (H, W) or (H, W, 3) as PNG (Pillow if present, else a .npy beside)."""
    try:
        from PIL import Image
    except ImportError:
        np.save(path.with_suffix(".npy"), array)
        return
    Image.fromarray(array.squeeze()).save(path)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--strands", type=int, default=20000)
    ap.add_argument("--size", type=int, default=512)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    hair = tress.generate("wavy", strands=args.strands, seed=3)
    lo, hi = hair.bounds
    centre = (lo + hi) / 2
    cams = tress.orbit(16, radius=70.0, elevation=5.0, target=centre, fov_y_deg=30.0,
                       width=args.size, height=args.size)
    r = tress.Renderer()
    start = time.perf_counter()
    maps = ("rgb", "mask", "body_mask", "depth", "orientation")
    strand = r.render(hair, cams, maps=maps + ("strand_id",), head="generated",
                      orientation="hairstep", rgb_format="srgb8")
    degrees = r.render(hair, cams, maps=("orientation",), head="generated", orientation="angle_deg")
    seconds = time.perf_counter() - start

    for v in range(len(cams)):
        save_png(args.out / f"{v:02d}_rgb.png", strand["rgb"][v])
        # HairStep: the strand map as 8-bit RGB, depth normalised to [0, 1] over the hair, nearer larger.
        save_png(args.out / f"{v:02d}_strand_map.png", np.round(strand["orientation"][v] * 255).astype(np.uint8))
        d = strand["depth"][v, :, :, 0]
        hair_px = strand["mask"][v, :, :, 0]
        norm = np.zeros_like(d)
        if hair_px.any():
            near, far = d[hair_px].min(), d[hair_px].max()
            norm[hair_px] = (far - d[hair_px]) / max(far - near, 1e-6)
        np.save(args.out / f"{v:02d}_depth.npy", norm.astype(np.float32))
        # NeuralHaircut: orientation in degrees as uint8, and the hair mask.
        save_png(args.out / f"{v:02d}_orientation.png", degrees["orientation"][v])
        save_png(args.out / f"{v:02d}_mask.png", hair_px.astype(np.uint8) * 255)
    print(f"{len(cams)} views of {len(hair)} strands at {args.size}x{args.size} in {seconds:.1f} s "
          f"on {r.adapter}; wrote {args.out}")


if __name__ == "__main__":
    main()
