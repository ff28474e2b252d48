"""Strands into voxel volumes (occupancy, orientation, density), as single-view hair
reconstruction trains on (NeuralHDHair's 96 × 128 × 128 fields)."""

from __future__ import annotations

from typing import Iterable, Optional, Sequence

import numpy as np

from . import _tress
from ._hair import Hair, _array

VOXEL_FIELDS = ("occupancy", "orientation", "density")
"""The volumes :func:`voxelize` returns. Arrays are indexed ``[d, h, w]``: ``d`` along world
z, ``h`` along world y, ``w`` along world x, each index increasing with its coordinate; voxel
``[d, h, w]`` covers ``min + (w, h, d) * size`` to ``min + (w + 1, h + 1, d + 1) * size`` with
``size = (max - min) / (W, H, D)``.

* ``occupancy``: (D, H, W) bool, a strand segment passes through the voxel (found exactly by
  walking each segment through the grid, not by sampling).
* ``orientation``: (D, H, W, 3) float32 (x, y, z), the mean unit tangent of the strands in the
  voxel: each segment's unit tangent ``t`` is first sign-normalised (``t`` or ``-t``, the one
  pointing down, ``t.y < 0``; if horizontal the one with ``t.z > 0``; if along x, ``t.x > 0``),
  then averaged weighted by the segment's length inside the voxel and normalised to unit
  length; (0, 0, 0) where empty.
* ``density``: (D, H, W) float32, the strand length inside the voxel (world units).
"""


def voxelize(hair: Hair, bounds: Optional[Sequence] = None, resolution: Sequence[int] = (96, 128, 128),
             fields: Iterable[str] = ("occupancy", "orientation")) -> dict:
    """``hair`` as voxel volumes over a ``resolution`` = (D, H, W) grid (see :data:`VOXEL_FIELDS`
    for the layout and each field). ``bounds``: ``(min xyz, max xyz)`` of the grid's box;
    default the hair's bounding box grown by one voxel on every side (voxels need not be
    cubes). Returns ``{field: array}`` for each of ``fields``, and ``"bounds"``: the box used,
    ``(min (3,), max (3,))`` float32. Runs on the CPU."""
    if not isinstance(hair, Hair):
        raise TypeError(f"hair must be a tress.Hair, got {type(hair).__name__}")
    fields = (fields,) if isinstance(fields, str) else tuple(fields)
    unknown = [f for f in fields if f not in VOXEL_FIELDS]
    if unknown or not fields:
        raise ValueError(f"fields: unknown field(s) {unknown}; valid: {', '.join(VOXEL_FIELDS)}")
    try:
        res = tuple(int(n) for n in resolution)
    except (TypeError, ValueError):
        raise ValueError(f"resolution must be 3 integers (D, H, W), got {resolution!r}") from None
    if len(res) != 3 or any(n < 3 for n in res) or any(n != r for n, r in zip(res, resolution)):
        raise ValueError(f"resolution must be 3 integers (D, H, W), each at least 3, got {resolution!r}")
    box = None
    if bounds is not None:
        b = _array(bounds, "bounds", np.float32, (2, 3))
        if not np.all(np.isfinite(b)) or not np.all(b[0] < b[1]):
            raise ValueError(f"bounds must be (min xyz, max xyz) with min < max on every axis, got {b.tolist()}")
        box = (tuple(float(x) for x in b[0]), tuple(float(x) for x in b[1]))
    out = _tress.voxelize(hair._arrays(), res, box)
    result = {f: out[f] for f in fields}
    lo, hi = out["bounds"]
    result["bounds"] = (np.asarray(lo, dtype=np.float32), np.asarray(hi, dtype=np.float32))
    return result
