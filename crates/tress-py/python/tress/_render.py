"""Renders as arrays."""

from __future__ import annotations

from typing import Iterable, Optional, Sequence, Union

import numpy as np

from . import _tress
from ._camera import Camera
from ._hair import Hair, _array

MAPS = ("rgb", "alpha")
"""The maps :meth:`Renderer.render` returns, each (views, H, W, C):

* ``rgb``: the frame as ``tress render`` draws it over ``background``; linear float32, or
  sRGB uint8 with ``rgb_format="srgb8"`` (what ``tress render`` writes to PNG).
* ``alpha``: float32 coverage in [0, 1] of the hair and the head (C = 1).
"""

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
               background: Sequence[float] = (0.0, 0.0, 0.0), rgb_format: str = "linear") -> dict:
        """Render ``hair`` from each camera; returns ``{map: array (views, H, W, C)}``.

        ``technique``: strands, volume, hybrid, auto or patches. ``head``: None, ``"generated"``
        (the head tress's generators grow hair from) or ``(vertices (V, 3), faces (F, 3))``.
        ``width``/``height`` default to the cameras' (all cameras must share one size).
        ``settings``: scene keys, e.g. ``{"strands.shading": "marschner"}`` (the scene file
        reference lists them). ``background``: linear RGB behind the hair.
        """
        if not isinstance(hair, Hair):
            raise TypeError(f"hair must be a tress.Hair, got {type(hair).__name__}")
        cams = [cameras] if isinstance(cameras, Camera) else list(cameras)
        if not cams:
            raise ValueError("cameras must hold at least one Camera")
        for c in cams:
            if not isinstance(c, Camera):
                raise TypeError(f"cameras must be tress.Camera objects, got {type(c).__name__}")
        w = cams[0].width if width is None else int(width)
        h = cams[0].height if height is None else int(height)
        if any((c.width, c.height) != (w, h) for c in cams):
            raise ValueError(f"every camera must be {w}x{h} (the render size); rebuild them with that size")
        maps = (maps,) if isinstance(maps, str) else tuple(maps)
        unknown = [m for m in maps if m not in MAPS]
        if unknown:
            raise ValueError(f"unknown map(s) {unknown}; valid maps: {', '.join(MAPS)}")
        if technique not in TECHNIQUES:
            raise ValueError(f"unknown technique {technique!r}; valid: {', '.join(TECHNIQUES)}")
        if rgb_format not in ("linear", "srgb8"):
            raise ValueError(f'rgb_format must be "linear" or "srgb8", got {rgb_format!r}')
        bg = _array(background, "background", np.float32, (3,))
        head_arrays = None
        if isinstance(head, str):
            if head != "generated":
                raise ValueError(f'head must be None, "generated" or (vertices, faces), got {head!r}')
            v, f = _tress.generated_head()
            head_arrays = (v, f.astype(np.uint32))
        elif head is not None:
            try:
                v, f = head
            except (TypeError, ValueError):
                raise TypeError("head must be None, \"generated\" or (vertices (V, 3), faces (F, 3))") from None
            v = _array(v, "head vertices", np.float32, ("V", 3))
            f = _array(f, "head faces", np.int64, ("F", 3))
            if len(f) and (f.min() < 0 or f.max() >= len(v)):
                raise ValueError(f"head faces must index the {len(v)} head vertices")
            head_arrays = (v, f.astype(np.uint32))
        sets = [f"{k}={_setting(v)}" for k, v in (settings or {}).items()]
        out = self._r.render(hair._arrays(), [c._matrices() for c in cams], w, h, technique,
                             head_arrays, sets, tuple(float(x) for x in bg))
        result = {}
        for m in maps:
            a = out[m]
            if m == "rgb" and rgb_format == "srgb8":
                a = _srgb8(a)
            result[m] = a
        return result


def _setting(v) -> str:
    """A settings value in the scene file's syntax (TOML)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_setting(x) for x in v) + "]"
    return repr(float(v)) if isinstance(v, float) else str(v)
