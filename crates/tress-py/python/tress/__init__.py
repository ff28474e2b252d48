"""tress: hair files into numpy arrays, cameras, and strand renders as arrays.

    import tress
    hair = tress.load("groom.hair")              # or .tfx, .usd*, .abc, .data, .bin
    hair.points, hair.offsets                    # (P, 3) float32, (N + 1,) int64
    cams = tress.orbit(16, radius=60, elevation=10, target=(0, -5, 0), width=512, height=512)
    out = tress.Renderer().render(hair, cams, maps=("rgb", "alpha"))
    out["rgb"].shape                             # (16, 512, 512, 3)
    ref = tress.Renderer().path_trace(hair, cams[:1], spp=64)  # CPU reference, (1, 512, 512, 3)
    vol = tress.voxelize(hair)                   # occupancy (96, 128, 128), orientation (..., 3)

Conventions (documented in each class): world units as in the file (tress's scenes use
centimetres, y up); ``Camera`` pixels follow OpenCV (x right, y down, pixel (0, 0)'s centre at
(0, 0)); images are row-major (views, H, W, C), row 0 at the top.
"""

from . import _tress
from ._camera import Camera, orbit
from ._dataset import render_dataset
from ._hair import Hair, generate, load, save, styles
from ._render import FIBER_KEYS, MAPS, ORIENTATIONS, Renderer, encode_orientation
from ._voxel import VOXEL_FIELDS, voxelize

HairError = _tress.HairError

__all__ = [
    "Camera",
    "FIBER_KEYS",
    "VOXEL_FIELDS",
    "Hair",
    "HairError",
    "MAPS",
    "ORIENTATIONS",
    "Renderer",
    "encode_orientation",
    "generate",
    "load",
    "orbit",
    "render_dataset",
    "save",
    "styles",
    "voxelize",
]
