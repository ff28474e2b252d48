"""Hair as numpy arrays: CSR strands (``points`` and ``offsets``) and optional attributes."""

from __future__ import annotations

import os
from typing import Optional, Sequence, Union

import numpy as np

from . import _tress

PathLike = Union[str, "os.PathLike[str]"]


def _array(value, name: str, dtype, shape: tuple) -> np.ndarray:
    """``value`` as a C-contiguous array of ``dtype``; ``shape`` names each free length (a
    string, e.g. ``("P", 3)``).

    Raises TypeError for something that is not numeric, ValueError for a wrong shape, both
    naming the argument and the shape expected.
    """
    try:
        a = np.asarray(value)
    except Exception as e:  # an object numpy cannot turn into an array
        raise TypeError(f"{name} must be an array of shape {_shape(shape)}: {e}") from None
    if a.dtype == object or not (
        np.issubdtype(a.dtype, np.number) or np.issubdtype(a.dtype, np.bool_)
    ):
        raise TypeError(f"{name} must be a numeric array of shape {_shape(shape)}, got dtype {a.dtype}")
    if a.ndim != len(shape) or any(isinstance(s, int) and s != d for s, d in zip(shape, a.shape)):
        raise ValueError(f"{name} must have shape {_shape(shape)}, got {a.shape}")
    return np.ascontiguousarray(a, dtype=dtype)


def _shape(shape: tuple) -> str:
    parts = [str(s) for s in shape]
    return "(" + ", ".join(parts) + ("," if len(parts) == 1 else "") + ")"


class Hair:
    """Strands as arrays, in CSR layout: strand ``i`` is ``points[offsets[i]:offsets[i + 1]]``.

    Attributes:
        points: (P, 3) float32 vertex positions.
        offsets: (N + 1,) int64, starting at 0 and ending at P.
        thickness: (P,) float32 strand diameter per vertex, or None.
        transparency: (P,) float32 per vertex (0 opaque), or None.
        color: (P, 3) float32 linear RGB per vertex, or None.
        uv: (N, 2) float32 per strand (its root's place on the scalp), or None.
    """

    __slots__ = ("points", "offsets", "thickness", "transparency", "color", "uv")

    def __init__(self, points, offsets, thickness=None, transparency=None, color=None, uv=None):
        self.points = _array(points, "points", np.float32, ("P", 3))
        self.offsets = _array(offsets, "offsets", np.int64, ("N + 1",))
        p = len(self.points)
        if len(self.offsets) < 2 or self.offsets[0] != 0 or self.offsets[-1] != p:
            raise ValueError(
                f"offsets must run from 0 to len(points) = {p} with at least one strand, "
                f"got {len(self.offsets)} offsets"
                + (f" from {self.offsets[0]} to {self.offsets[-1]}" if len(self.offsets) else "")
            )
        if np.any(np.diff(self.offsets) < 1):
            raise ValueError("offsets must increase: every strand needs at least one vertex")
        n = len(self.offsets) - 1
        self.thickness = None if thickness is None else _array(thickness, "thickness", np.float32, (p,))
        self.transparency = (
            None if transparency is None else _array(transparency, "transparency", np.float32, (p,))
        )
        self.color = None if color is None else _array(color, "color", np.float32, (p, 3))
        self.uv = None if uv is None else _array(uv, "uv", np.float32, (n, 2))

    @classmethod
    def _wrap(cls, d: dict) -> "Hair":
        """Arrays from the extension (already the right dtypes), taken as they are."""
        h = cls.__new__(cls)
        h.points = d["points"]
        h.offsets = d["offsets"]
        h.thickness = d.get("thickness")
        h.transparency = d.get("transparency")
        h.color = d.get("color")
        h.uv = d.get("uv")
        return h

    def _arrays(self) -> dict:
        return {
            "points": self.points,
            "offsets": self.offsets,
            "thickness": self.thickness,
            "transparency": self.transparency,
            "color": self.color,
            "uv": self.uv,
        }

    @classmethod
    def from_arrays(cls, points, offsets, thickness=None, transparency=None, color=None, uv=None) -> "Hair":
        """Hair from CSR arrays (any numeric dtype; copied only where the dtype or layout differs)."""
        return cls(points, offsets, thickness, transparency, color, uv)

    @classmethod
    def from_padded(cls, strands) -> "Hair":
        """Hair from an (N, V, 3) array: N strands of V vertices each."""
        a = _array(strands, "strands", np.float32, ("N", "V", 3))
        n, v, _ = a.shape
        if n == 0 or v == 0:
            raise ValueError(f"strands must have shape (N, V, 3) with N, V >= 1, got {a.shape}")
        return cls(a.reshape(n * v, 3), np.arange(0, n * v + 1, v, dtype=np.int64))

    def to_padded(self, n: int) -> np.ndarray:
        """The strands as an (N, n, 3) array: as they are when every strand has ``n`` vertices
        (a view, no copy), otherwise each resampled to ``n`` vertices by arc length."""
        if np.all(np.diff(self.offsets) == n):
            return self.points.reshape(len(self), n, 3)
        return self.resample(n).points.reshape(len(self), n, 3)

    def resample(self, n: int = 0, by: str = "arclength", segment_length: float = 0.0) -> "Hair":
        """Every strand resampled: ``n`` vertices placed uniformly by arc length
        (``by="arclength"``, root and tip kept), or segments of ``segment_length``
        (``by="length"``). Attributes are interpolated."""
        if by not in ("arclength", "length"):
            raise ValueError(f'by must be "arclength" or "length", got {by!r}')
        return Hair._wrap(_tress.resample(self._arrays(), int(n), by, float(segment_length)))

    def follow(self, count: int, mode: str = "interpolate", radius: float = 0.7,
               tip_separation: float = 1.0, seed: int = 0) -> "Hair":
        """These strands as guides with ``count`` follow hairs after each: blended from the
        three surrounding guides (``"interpolate"``) or offset copies (``"offset"``, TressFX);
        ``radius`` in times the roots' spacing."""
        return Hair._wrap(_tress.follow(self._arrays(), int(count), mode, float(radius),
                                        float(tip_separation), int(seed)))

    def __len__(self) -> int:
        return len(self.offsets) - 1

    @property
    def vertex_counts(self) -> np.ndarray:
        """(N,) int64 vertices per strand."""
        return np.diff(self.offsets)

    @property
    def bounds(self) -> tuple:
        """(min, max) corners of the box around every vertex, each a (3,) float32 array."""
        return self.points.min(axis=0), self.points.max(axis=0)

    def strand(self, i: int) -> np.ndarray:
        """The (V, 3) vertices of strand ``i`` (a view, no copy)."""
        if not -len(self) <= i < len(self):
            raise IndexError(f"strand {i} of {len(self)}")
        i %= len(self)
        return self.points[self.offsets[i]:self.offsets[i + 1]]

    def __repr__(self) -> str:
        extra = [k for k in ("thickness", "transparency", "color", "uv") if getattr(self, k) is not None]
        return f"Hair({len(self)} strands, {len(self.points)} vertices" + (
            ", " + ", ".join(extra) if extra else "") + ")"


def load(path: Union[PathLike, Sequence[PathLike]], frame: int = 0, cubic_segments: int = 4) -> Hair:
    """Read a hair file, or several merged in order, by extension: ``.hair``, ``.tfx``,
    ``.usda``/``.usdc``/``.usdz``/``.usd``, ``.abc``, USC-HairSalon ``.data``, CT2Hair ``.bin``.

    ``frame`` picks the sample of an animated Alembic or USD cache. A file that cannot be read
    raises ``tress.HairError`` with the line ``tress`` prints (the file, then the problem).
    """
    paths = [path] if isinstance(path, (str, os.PathLike)) else list(path)
    if not paths:
        raise ValueError("load needs at least one path")
    for p in paths:
        if not isinstance(p, (str, os.PathLike)):
            raise TypeError(f"paths must be str or os.PathLike, got {type(p).__name__}")
    return Hair._wrap(_tress.load([os.fspath(p) for p in paths], int(frame), int(cubic_segments)))


def save(path: PathLike, hair: Hair) -> None:
    """Write ``hair`` to ``path``, format by extension: ``.hair``, ``.tfx``, ``.usda``,
    ``.usdc``, ``.usd``, ``.abc``, ``.data``."""
    if not isinstance(hair, Hair):
        raise TypeError(f"hair must be a tress.Hair, got {type(hair).__name__}")
    _tress.save(os.fspath(path), hair._arrays())


def styles() -> list:
    """The generator styles: straight, wavy, curly, ponytail, fur."""
    return list(_tress.styles())


def generate(style: str, strands: Optional[int] = None, vertices: Optional[int] = None,
             length: Optional[float] = None, seed: Optional[int] = None, **params) -> Hair:
    """A generated groom, as ``tress generate`` makes it: ``style`` one of :func:`styles`;
    absent arguments take the style's own values. Further keywords: ``curl_radius``,
    ``curl_frequency``, ``clumping``, ``noise``, ``thickness``."""
    known = {"curl_radius", "curl_frequency", "clumping", "noise", "thickness"}
    unknown = set(params) - known
    if unknown:
        raise TypeError(f"unknown generator parameters {sorted(unknown)}; valid: {sorted(known)}")
    return Hair._wrap(_tress.generate(style, strands, vertices, length, seed, **params))
