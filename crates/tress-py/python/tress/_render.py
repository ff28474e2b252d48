"""Renders as arrays."""

from __future__ import annotations

from typing import Iterable, Optional, Sequence, Union

import numpy as np

from . import _tress
from ._camera import Camera
from ._hair import Hair, _array

MAPS = ("rgb", "alpha", "depth", "mask", "body_mask", "strand_id", "direction", "orientation")
"""The maps :meth:`Renderer.render` returns, each shaped (views, H, W, C), row 0 at the top.

Shaded (the technique's frame):

* ``rgb``: the frame as ``tress render`` draws it over ``background``; linear float32, or
  sRGB uint8 with ``rgb_format="srgb8"`` (what ``tress render`` writes to PNG).
* ``alpha``: float32 coverage in [0, 1] of the hair and the head (C = 1).

Geometry (strands drawn as 1-pixel lines and the head as triangles, the nearest surface wins;
the same for every technique):

* ``depth``: float32 depth of the nearest surface (hair or head) along the view direction
  (OpenCV's camera z, positive in front; the distance along the axis for orthographic
  cameras), ``inf`` where empty (C = 1).
* ``mask``: bool, a strand is the nearest surface (C = 1).
* ``body_mask``: bool, the head covers the pixel, behind hair or not (C = 1).
* ``strand_id``: int32 index of the nearest strand in ``hair``, −1 where no strand is nearest
  (C = 1).
* ``direction``: float32 (dx, dy), the nearest strand segment's projected direction from root
  to tip, unit length in pixels, x right and y down; (0, 0) where no strand (C = 2).
* ``orientation``: the direction in the encoding ``orientation=`` names (:data:`ORIENTATIONS`).
"""

ORIENTATIONS = ("angle", "angle_deg", "hairstep", "monohair", "monohair_undirected")
"""Encodings of the ``orientation`` map. With (dx, dy) the ``direction`` map (y down) and
θ = atan2(−dy, dx) the directed angle in the image, counter-clockwise from +x with y up:

* ``"angle"``: θ mod π in [0, π), float32 radians, undirected (C = 1); 0 where no strand.
* ``"angle_deg"``: that angle in whole degrees, round(θ · 180 / π) mod 180, uint8 (C = 1): the
  encoding of NeuralHaircut's orientation PNGs.
* ``"hairstep"``: HairStep's strand map, float32 (C = 3): R = mask + 0.5 × body_mask where no
  strand is nearest (1 on hair, 0.5 on visible body, 0 elsewhere); G, B = the directed 2-D
  direction d = (cos θ, sin θ) (y up) as ((−d.x + 1) / 2, (d.y + 1) / 2) on hair, 0 elsewhere.
* ``"monohair"``: MonoHair's directed map ((cos θ, sin θ, 0) + 1) / 2 on hair, 0 elsewhere,
  float32 (C = 3).
* ``"monohair_undirected"``: ((cos 2θ, sin 2θ, 0) + 1) / 2 on hair, 0 elsewhere, float32 (C = 3).
"""

SHADED = ("rgb", "alpha")

TECHNIQUES = ("strands", "volume", "hybrid", "auto", "patches")


def _srgb8(linear: np.ndarray) -> np.ndarray:
    c = np.clip(linear, 0.0, 1.0)
    s = np.where(c <= 0.0031308, c * 12.92, 1.055 * np.power(c, 1 / 2.4) - 0.055)
    return np.round(s * 255.0).astype(np.uint8)


class Renderer:
    """One GPU device, opened once and reused by every render (the first Vulkan adapter; set
    ``WGPU_ADAPTER_NAME`` to choose). Without any adapter it raises ``RuntimeError`` saying how
    to install a Vulkan driver (``apt-get install mesa-vulkan-drivers`` gives lavapipe, which
    renders on the CPU)."""

    def __init__(self):
        self._r = _tress.Renderer()

    @property
    def adapter(self) -> str:
        """The adapter's name and backend."""
        return self._r.adapter

    def render(self, hair: Hair, cameras: Union[Camera, Sequence[Camera]], technique: str = "strands",
               maps: Iterable[str] = ("rgb", "alpha"), head=None, width: Optional[int] = None,
               height: Optional[int] = None, settings: Optional[dict] = None,
               background: Sequence[float] = (0.0, 0.0, 0.0), rgb_format: str = "linear",
               orientation: str = "angle") -> dict:
        """Render ``hair`` from each camera; returns ``{map: array (views, H, W, C)}``.

        ``technique``: strands, volume, hybrid, auto or patches. ``head``: None, ``"generated"``
        (the head tress's generators grow hair from) or ``(vertices (V, 3), faces (F, 3))``.
        ``width``/``height`` default to the cameras' (all cameras must share one size).
        ``settings``: scene keys, e.g. ``{"strands.shading": "marschner"}`` (the scene file
        reference lists them). ``background``: linear RGB behind the hair. ``maps``: any of
        :data:`MAPS`; ``orientation``: the encoding of the ``orientation`` map
        (:data:`ORIENTATIONS`).
        """
        if not isinstance(hair, Hair):
            raise TypeError(f"hair must be a tress.Hair, got {type(hair).__name__}")
        cams = _cameras(cameras)
        w = cams[0].width if width is None else int(width)
        h = cams[0].height if height is None else int(height)
        if (cams[0].width, cams[0].height) != (w, h):
            raise ValueError(f"every camera must be {w}x{h} (the render size); rebuild them with that size")
        maps = (maps,) if isinstance(maps, str) else tuple(maps)
        unknown = [m for m in maps if m not in MAPS]
        if unknown:
            raise ValueError(f"unknown map(s) {unknown}; valid maps: {', '.join(MAPS)}")
        if technique not in TECHNIQUES:
            raise ValueError(f"unknown technique {technique!r}; valid: {', '.join(TECHNIQUES)}")
        if orientation not in ORIENTATIONS:
            raise ValueError(f"unknown orientation encoding {orientation!r}; valid: {', '.join(ORIENTATIONS)}")
        if rgb_format not in ("linear", "srgb8"):
            raise ValueError(f'rgb_format must be "linear" or "srgb8", got {rgb_format!r}')
        bg = _array(background, "background", np.float32, (3,))
        head_arrays = _head(head)
        sets = [f"{k}={_setting(v)}" for k, v in (settings or {}).items()]
        shaded = any(m in SHADED for m in maps)
        geometry = any(m not in SHADED for m in maps)
        out = self._r.render(hair._arrays(), [c._matrices() for c in cams], w, h, technique,
                             head_arrays, sets, tuple(float(x) for x in bg), shaded, geometry)
        result = {}
        for m in maps:
            if m in SHADED:
                a = out[m]
                result[m] = _srgb8(a) if m == "rgb" and rgb_format == "srgb8" else a
            else:
                result[m] = _geometry_map(m, out, orientation)
        return result

    def path_trace(self, hair: Hair, cameras: Union[Camera, Sequence[Camera]], spp: int = 16,
                   shading: str = "marschner", fiber: Optional[dict] = None, head=None,
                   settings: Optional[dict] = None, background: Sequence[float] = (0.0, 0.0, 0.0),
                   seed: int = 0) -> np.ndarray:
        """The CPU reference path tracer (what ``tress reference`` runs) through each camera,
        exactly as given (any view and projection matrices); float32 linear RGB shaped
        (views, H, W, 3) over ``background``. Needs no GPU; the same ``seed`` gives the same
        frames.

        ``shading``: ``"marschner"`` (Chiang et al. 2016's fibres, a path tracer) or
        ``"kajiya-kay"``. ``fiber``: ``[hair.material]`` keys of the fibre (:data:`FIBER_KEYS`),
        e.g. ``{"eumelanin": 0.3, "beta_m": 0.25}``. ``head`` as for :meth:`render`.
        ``settings``: scene keys as for :meth:`render`, and the tracer's own as ``trace.NAME``
        (``trace.bounces``, ``trace.ao_samples``, ``trace.width``...).
        """
        cams = _cameras(cameras)
        fiber = dict(fiber or {})
        unknown = [k for k in fiber if k not in FIBER_KEYS]
        if unknown:
            raise ValueError(f"unknown fiber key(s) {unknown}; valid: {', '.join(FIBER_KEYS)}")
        if int(spp) < 1:
            raise ValueError(f"spp must be at least 1, got {spp}")
        bg = _array(background, "background", np.float32, (3,))
        return _tress.path_trace(hair._arrays(), [c._matrices() for c in cams], cams[0].width, cams[0].height,
                                 int(spp), shading, [(k, _setting(v)) for k, v in fiber.items()],
                                 _head(head), [f"{k}={_setting(v)}" for k, v in (settings or {}).items()],
                                 tuple(float(x) for x in bg), int(seed))


FIBER_KEYS = ("eumelanin", "pheomelanin", "sigma_a", "target_color", "beta_m", "beta_n", "alpha_deg", "eta",
              "thickness")
"""The ``fiber`` keys of :meth:`Renderer.path_trace`: the scene's ``[hair.material]`` keys of the
physically based fibre (the scene file reference): melanin concentrations ``eumelanin`` and
``pheomelanin``, or ``sigma_a`` (absorption per fibre radius, RGB), or ``target_color`` (RGB);
roughness ``beta_m`` and ``beta_n``; cuticle tilt ``alpha_deg``; index of refraction ``eta``;
and the strand diameter ``thickness`` (world units; default: the hair's own)."""


def _cameras(cameras) -> list:
    """One camera or a sequence of them, checked: at least one, all tress.Camera, one size."""
    cams = [cameras] if isinstance(cameras, Camera) else list(cameras)
    if not cams:
        raise ValueError("cameras must hold at least one Camera")
    for c in cams:
        if not isinstance(c, Camera):
            raise TypeError(f"cameras must be tress.Camera objects, got {type(c).__name__}")
    if any((c.width, c.height) != (cams[0].width, cams[0].height) for c in cams):
        raise ValueError(f"every camera must be {cams[0].width}x{cams[0].height}; rebuild them with one size")
    return cams


def _head(head):
    """``head`` as the extension takes it: None or (vertices float32, faces uint32)."""
    if head is None:
        return None
    if isinstance(head, str):
        if head != "generated":
            raise ValueError(f'head must be None, "generated" or (vertices, faces), got {head!r}')
        v, f = _tress.generated_head()
        return v, f.astype(np.uint32)
    try:
        v, f = head
    except (TypeError, ValueError):
        raise TypeError("head must be None, \"generated\" or (vertices (V, 3), faces (F, 3))") from None
    v = _array(v, "head vertices", np.float32, ("V", 3))
    f = _array(f, "head faces", np.int64, ("F", 3))
    if len(f) and (f.min() < 0 or f.max() >= len(v)):
        raise ValueError(f"head faces must index the {len(v)} head vertices")
    return v, f.astype(np.uint32)


def _geometry_map(name: str, out: dict, orientation: str) -> np.ndarray:
    ids = out["strand_id"]
    mask = ids >= 0
    if name == "depth":
        return out["depth"]
    if name == "mask":
        return mask
    if name == "body_mask":
        return out["head"]
    if name == "strand_id":
        return np.where(mask, ids, np.int32(-1)).astype(np.int32)
    if name == "direction":
        return out["direction"]
    return encode_orientation(out["direction"], mask, out["head"], orientation)


def encode_orientation(direction: np.ndarray, mask: np.ndarray, body: np.ndarray, encoding: str) -> np.ndarray:
    """The ``direction`` map (…, 2) in one of :data:`ORIENTATIONS` (see there)."""
    dx, dy = direction[..., 0:1], direction[..., 1:2]
    theta = np.arctan2(-dy, dx)  # y up, counter-clockwise from +x
    m = mask.astype(np.float32)
    if encoding == "angle":
        return (np.mod(theta, np.pi) * m).astype(np.float32)
    if encoding == "angle_deg":
        deg = np.mod(np.round(np.degrees(np.mod(theta, np.pi))), 180)
        return (deg * m).astype(np.uint8)
    if encoding == "hairstep":
        r = m + 0.5 * body.astype(np.float32) * (1 - m)
        g = (-np.cos(theta) + 1) / 2 * m
        b = (np.sin(theta) + 1) / 2 * m
        return np.concatenate([r, g, b], axis=-1).astype(np.float32)
    k = 2.0 if encoding == "monohair_undirected" else 1.0
    c = (np.cos(k * theta) + 1) / 2 * m
    s = (np.sin(k * theta) + 1) / 2 * m
    return np.concatenate([c, s, 0.5 * m], axis=-1).astype(np.float32)


def _setting(v) -> str:
    """A settings value in the scene file's syntax (TOML)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_setting(x) for x in v) + "]"
    return repr(float(v)) if isinstance(v, float) else str(v)
