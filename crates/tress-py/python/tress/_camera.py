"""Cameras, with their conventions written down.

World space is right-handed, in the hair file's units. Each camera holds two 4 × 4 float32
matrices, row-major, applied to column vectors:

* ``view`` (world → view): OpenGL's view space, x right, y up, looking down −z.
* ``projection`` (view → clip): wgpu's clip space, x and y in [−1, 1] with +y at the top row
  of the image, depth in [0, 1] (0 at ``near``).

Pixels follow OpenCV: u to the right, v down, the centre of pixel (column i, row j) at
(u, v) = (i, j). :meth:`Camera.project` returns (u, v) and the depth along the view direction
(OpenCV's camera z, positive in front). Images are (H, W, C) with row 0 at the top.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

_FLIP = np.diag([1.0, -1.0, -1.0, 1.0])  # OpenCV camera axes <-> OpenGL view axes


def _vec3(v, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be 3 finite numbers, got {v!r}")
    return a


def _size(width, height):
    if int(width) < 1 or int(height) < 1:
        raise ValueError(f"width and height must be at least 1, got {width} x {height}")
    return int(width), int(height)


def _look_at(eye, target, up) -> np.ndarray:
    """World → view (OpenGL axes), as glam's ``Mat4::look_at_rh``."""
    f = target - eye
    if np.linalg.norm(f) == 0:
        raise ValueError("eye and target must differ")
    f = f / np.linalg.norm(f)
    s = np.cross(f, up)
    if np.linalg.norm(s) < 1e-12:
        raise ValueError("up must not be parallel to the view direction")
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


class Camera:
    """A camera: ``view`` (world → view) and ``projection`` (view → clip) matrices for an
    image of ``width`` × ``height`` pixels (see the module's conventions)."""

    def __init__(self, view, projection, width: int, height: int):
        self.view = np.ascontiguousarray(np.asarray(view, dtype=np.float64).reshape(4, 4))
        self.projection = np.ascontiguousarray(np.asarray(projection, dtype=np.float64).reshape(4, 4))
        self.width, self.height = _size(width, height)
        m = self.projection @ self.view
        if not np.all(np.isfinite(m)) or abs(np.linalg.det(m)) < 1e-30:
            raise ValueError("camera matrices must be finite and invertible")

    # -- constructors --------------------------------------------------------------------

    @classmethod
    def look_at(cls, eye, target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov_y_deg: float = 35.0,
                width: int = 512, height: int = 512, near: float = 0.1, far: float = 1000.0) -> "Camera":
        """A pinhole camera at ``eye`` looking at ``target``, ``fov_y_deg`` the vertical field of
        view, principal point at the image centre (what ``[camera]`` in a scene file makes)."""
        width, height = _size(width, height)
        if not 0 < fov_y_deg < 180:
            raise ValueError(f"fov_y_deg must lie in (0, 180), got {fov_y_deg}")
        if not 0 < near < far:
            raise ValueError(f"need 0 < near < far, got near={near}, far={far}")
        h = 1.0 / math.tan(math.radians(fov_y_deg) / 2)
        w = h * height / width
        r = far / (near - far)
        p = np.array([[w, 0, 0, 0], [0, h, 0, 0], [0, 0, r, r * near], [0, 0, -1, 0]], dtype=np.float64)
        return cls(_look_at(_vec3(eye, "eye"), _vec3(target, "target"), _vec3(up, "up")), p, width, height)

    @classmethod
    def from_opencv(cls, K, R, t, width: int, height: int, near: float = 0.01, far: float = 1000.0) -> "Camera":
        """A camera from OpenCV's calibration: a point ``X`` in the world is ``x = R @ X + t`` in
        camera space (x right, y down, z forward) and projects to ``K @ x / x[2]`` in pixels
        (u right, v down, pixel centres at whole numbers). ``K`` is 3 × 3 (skew allowed)."""
        width, height = _size(width, height)
        K = np.asarray(K, dtype=np.float64)
        R = np.asarray(R, dtype=np.float64)
        t = np.asarray(t, dtype=np.float64).reshape(-1)
        if K.shape != (3, 3) or R.shape != (3, 3) or t.shape != (3,):
            raise ValueError(f"K and R must be (3, 3) and t (3,), got {K.shape}, {R.shape}, {t.shape}")
        if not np.allclose(R @ R.T, np.eye(3), atol=1e-4) or np.linalg.det(R) < 0:
            raise ValueError("R must be a rotation (orthonormal, determinant +1)")
        if not 0 < near < far:
            raise ValueError(f"need 0 < near < far, got near={near}, far={far}")
        fx, s, cx, fy, cy = K[0, 0], K[0, 1], K[0, 2], K[1, 1], K[1, 2]
        W, H = width, height
        r = far / (near - far)
        # Clip = P @ view_gl with view_gl = diag(1, -1, -1, 1) @ [R t]: derived in the module docs.
        p = np.array([
            [2 * fx / W, -2 * s / W, 1 - 2 * (cx + 0.5) / W, 0],
            [0, 2 * fy / H, 2 * (cy + 0.5) / H - 1, 0],
            [0, 0, r, r * near],
            [0, 0, -1, 0],
        ], dtype=np.float64)
        rt = np.eye(4)
        rt[:3, :3], rt[:3, 3] = R, t
        return cls(_FLIP @ rt, p, width, height)

    @classmethod
    def orthographic(cls, eye, target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), extent: float = 2.0,
                     width: int = 512, height: int = 512, near: float = 0.01, far: float = 1000.0) -> "Camera":
        """An orthographic camera (as PIFu and HairStep render): looking from ``eye`` towards
        ``target``, the image ``extent`` world units tall (and ``extent * width / height`` wide),
        centred on the view axis: one world unit is ``height / extent`` pixels, and a point at
        view-space (x, y) lands on u = W / 2 + x * H / extent − 0.5, v = H / 2 − y * H / extent − 0.5."""
        width, height = _size(width, height)
        if not extent > 0:
            raise ValueError(f"extent must be positive, got {extent}")
        if not 0 <= near < far:
            raise ValueError(f"need 0 <= near < far, got near={near}, far={far}")
        top = extent / 2
        right = top * width / height
        c = 1.0 / (near - far)
        p = np.array([[1 / right, 0, 0, 0], [0, 1 / top, 0, 0], [0, 0, c, c * near], [0, 0, 0, 1]],
                     dtype=np.float64)
        return cls(_look_at(_vec3(eye, "eye"), _vec3(target, "target"), _vec3(up, "up")), p, width, height)

    # -- properties ----------------------------------------------------------------------

    @property
    def is_orthographic(self) -> bool:
        return self.projection[3, 3] != 0 and self.projection[3, 2] == 0

    @property
    def R(self) -> np.ndarray:
        """World → OpenCV camera rotation (3, 3)."""
        return (_FLIP @ self.view)[:3, :3]

    @property
    def t(self) -> np.ndarray:
        """World → OpenCV camera translation (3,)."""
        return (_FLIP @ self.view)[:3, 3]

    @property
    def K(self) -> np.ndarray:
        """OpenCV intrinsics (3, 3) of a perspective camera."""
        if self.is_orthographic:
            raise ValueError("an orthographic camera has no pinhole intrinsics")
        p, W, H = self.projection, self.width, self.height
        fx, fy = p[0, 0] * W / 2, p[1, 1] * H / 2
        s = -p[0, 1] * W / 2
        cx = (1 - p[0, 2]) * W / 2 - 0.5
        cy = (p[1, 2] + 1) * H / 2 - 0.5
        return np.array([[fx, s, cx], [0, fy, cy], [0, 0, 1]])

    @property
    def eye(self) -> np.ndarray:
        """The camera's position in the world (3,)."""
        return np.linalg.inv(self.view)[:3, 3]

    # -- projection ----------------------------------------------------------------------

    def project(self, points) -> tuple:
        """World points (N, 3) → (uv (N, 2) pixels in OpenCV's convention, depth (N,) along the
        view direction, positive in front)."""
        x = np.asarray(points, dtype=np.float64)
        if x.ndim != 2 or x.shape[1] != 3:
            raise ValueError(f"points must have shape (N, 3), got {x.shape}")
        h = np.concatenate([x, np.ones((len(x), 1))], axis=1)
        v = h @ self.view.T
        c = v @ self.projection.T
        ndc = c[:, :3] / c[:, 3:4]
        u = (ndc[:, 0] + 1) / 2 * self.width - 0.5
        w = (1 - ndc[:, 1]) / 2 * self.height - 0.5
        return np.stack([u, w], axis=1), -v[:, 2]

    def _matrices(self):
        return (np.ascontiguousarray(self.view, dtype=np.float32),
                np.ascontiguousarray(self.projection, dtype=np.float32))

    def __repr__(self) -> str:
        kind = "orthographic" if self.is_orthographic else "perspective"
        return f"Camera({kind}, {self.width}x{self.height}, eye={np.round(self.eye, 3).tolist()})"


def orbit(n: int, radius: float, elevation: float = 0.0, target: Sequence[float] = (0.0, 0.0, 0.0),
          fov_y_deg: float = 35.0, width: int = 512, height: int = 512, start: float = 0.0,
          near: float = 0.1, far: float = 1000.0) -> list:
    """``n`` cameras evenly around the y axis through ``target``, ``radius`` away, raised by
    ``elevation`` degrees, the first at azimuth ``start`` degrees (0: on +z, the face's side
    for tress's generated heads), looking at ``target``."""
    if int(n) < 1:
        raise ValueError(f"n must be at least 1, got {n}")
    if not radius > 0:
        raise ValueError(f"radius must be positive, got {radius}")
    tgt = _vec3(target, "target")
    el = math.radians(elevation)
    cams = []
    for i in range(int(n)):
        az = math.radians(start + 360.0 * i / int(n))
        eye = tgt + radius * np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])
        cams.append(Camera.look_at(eye, tgt, (0, 1, 0), fov_y_deg, width, height, near, far))
    return cams
