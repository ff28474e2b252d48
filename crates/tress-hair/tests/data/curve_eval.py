"""Reference evaluation of curves, for the fixture scripts (make_usd.py, make_abc.py).

It states, independently of the Rust reader, what a cubic or NURBS curve tessellates to under
tress's documented rule (`tress_hair::formats::curves`): every span of a cubic curve, and every
knot span of positive length of a NURBS curve, is cut into `segments` equal parameter steps, the
spans sharing their end vertices, so a curve of `s` spans becomes `s * segments + 1` vertices
(a periodic curve repeats its first vertex at the end).

Basis matrices are the ones of the USD `BasisCurves` documentation (row vector [t^3 t^2 t 1]
times the matrix times the four control points). NURBS are evaluated with the Cox-de Boor
recursion of the basis functions (not de Boor's algorithm, which the Rust reader uses).
"""

BEZIER = [[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 3, 0, 0], [1, 0, 0, 0]]
BSPLINE = [[-1 / 6, 3 / 6, -3 / 6, 1 / 6], [3 / 6, -6 / 6, 3 / 6, 0], [-3 / 6, 0, 3 / 6, 0],
           [1 / 6, 4 / 6, 1 / 6, 0]]
CATMULL_ROM = [[-0.5, 1.5, -1.5, 0.5], [1, -2.5, 2, -0.5], [-0.5, 0, 0.5, 0], [0, 1, 0, 0]]
MATRICES = {"bezier": BEZIER, "bspline": BSPLINE, "catmullRom": CATMULL_ROM}


def _weights(matrix, t):
    powers = [t * t * t, t * t, t, 1.0]
    return [sum(powers[r] * matrix[r][c] for r in range(4)) for c in range(4)]


def spans(n, basis, wrap):
    """The control-point indices (into the phantom-extended list) of each span."""
    if basis == "bezier":
        if wrap == "periodic":
            return [[(3 * s + k) % n for k in range(4)] for s in range(n // 3)]
        return [[3 * s + k for k in range(4)] for s in range((n - 1) // 3)]
    if wrap == "periodic":
        return [[(s + k) % n for k in range(4)] for s in range(n)]
    if wrap == "pinned":
        # indices into [phantom0] + points + [phantom1]
        return [[s + k for k in range(4)] for s in range(n - 1)]
    return [[s + k for k in range(4)] for s in range(n - 3)]


def extended(values, basis, wrap, lerp):
    """The control values with pinned phantom points added (bspline / catmullRom only)."""
    if wrap == "pinned" and basis != "bezier":
        first = lerp(values[0], values[1], -1.0)
        last = lerp(values[-1], values[-2], -1.0)
        return [first] + list(values) + [last]
    return list(values)


def _lerp3(a, b, t):
    return tuple(a[i] + (b[i] - a[i]) * t for i in range(3))


def _lerp1(a, b, t):
    return a + (b - a) * t


def cubic(points, basis, wrap, segments):
    """Tessellate one cubic curve (a list of xyz tuples) to a list of xyz tuples."""
    matrix = MATRICES[basis]
    ext = extended(points, basis, wrap, _lerp3)
    out = []
    for si, span in enumerate(spans(len(points), basis, wrap)):
        for k in range(0 if si == 0 else 1, segments + 1):
            w = _weights(matrix, k / segments)
            out.append(tuple(sum(w[j] * ext[span[j]][i] for j in range(4)) for i in range(3)))
    return out


def cubic_scalar(values, basis, wrap, segments):
    """A per-vertex scalar (e.g. a width) along one cubic curve, like the points."""
    matrix = MATRICES[basis]
    ext = extended(values, basis, wrap, _lerp1)
    out = []
    for si, span in enumerate(spans(len(values), basis, wrap)):
        for k in range(0 if si == 0 else 1, segments + 1):
            w = _weights(matrix, k / segments)
            out.append(sum(w[j] * ext[span[j]] for j in range(4)))
    return out


def _basis(i, p, u, knots):
    if p == 0:
        if knots[i] <= u < knots[i + 1]:
            return 1.0
        # the curve's last parameter belongs to the last non-empty span
        if u == knots[-1] and knots[i] < knots[i + 1] == knots[-1]:
            return 1.0
        return 0.0
    a = 0.0
    if knots[i + p] != knots[i]:
        a = (u - knots[i]) / (knots[i + p] - knots[i]) * _basis(i, p - 1, u, knots)
    b = 0.0
    if knots[i + p + 1] != knots[i + 1]:
        b = (knots[i + p + 1] - u) / (knots[i + p + 1] - knots[i + 1]) * _basis(i + 1, p - 1, u, knots)
    return a + b


def nurbs(points, order, knots, segments, weights=None):
    """Tessellate one NURBS curve: every knot span of positive length inside the curve's domain
    [knots[order - 1], knots[n]] into `segments` steps."""
    n = len(points)
    p = order - 1
    weights = weights or [1.0] * n
    breaks = [knots[i] for i in range(p, n + 1)]
    params = []
    for a, b in zip(breaks, breaks[1:]):
        if b > a:
            start = 0 if not params else 1
            params.extend(a + (b - a) * k / segments for k in range(start, segments + 1))
    out = []
    for u in params:
        basis = [_basis(i, p, u, knots) * weights[i] for i in range(n)]
        total = sum(basis)
        out.append(tuple(sum(basis[i] * points[i][c] for i in range(n)) / total for c in range(3)))
    return out


def bounds(points):
    return [min(p[i] for p in points) for i in range(3)], [max(p[i] for p in points) for i in range(3)]
