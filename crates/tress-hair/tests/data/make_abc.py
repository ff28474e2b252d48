"""Write the Alembic test files with the PyAlembic bindings (`pip install alembic3d`, the
Alembic C++ library itself) and state what each must read as in abc_expected.json (read by
crates/tress-hair/tests/formats_abc.rs and crates/tress-alembic/tests/).

Run from this folder: `python3 make_abc.py`. The generated files are committed, so the tests need
no Python. World positions come from Alembic's own matrices (`XformSample.getMatrix()` composed
down the hierarchy), cubic tessellation from curve_eval.py (4 segments per span).

Files:
- groom.abc (Ogawa):
  /groom            IXform: translate (1, 2, 3), rotate 90 degrees about y, scale 2
  /groom/strands    ICurves linear, 3 curves of 3, 4 and 2 vertices, width per vertex, and the
                    Unreal groom attributes: groom_color (per vertex), groom_root_uv (per curve),
                    groom_guide (per curve: the third curve is a guide, which tress skips)
  /groom/inner      IXform: translate (0, -1, 0)
  /groom/inner/bspline  ICurves cubic b-spline, 4 and 5 vertices, one constant width
  /catmull          ICurves cubic Catmull-Rom, 5 vertices, width per curve
  /bezier           ICurves cubic Bezier, 4 and 7 vertices, no width
- hdf5.abc: the 8-byte HDF5 signature and zeros (what an HDF5-based Alembic starts with).
- truncated.abc: the first 200 bytes of groom.abc. bad_magic.abc: groom.abc with "Ogawa" changed.
"""

import json
import os

import imath
from alembic3d import Abc, AbcGeom

import curve_eval

SEGMENTS = 4
HERE = os.path.dirname(os.path.abspath(__file__))
BASES = {
    AbcGeom.BasisType.kBsplineBasis: "bspline",
    AbcGeom.BasisType.kCatmullromBasis: "catmullRom",
    AbcGeom.BasisType.kBezierBasis: "bezier",
}


def path(name):
    return os.path.join(HERE, name)


def strand(x, z, n, length=1.0, bend=0.0):
    return [(x + bend * (i / max(n - 1, 1)) ** 2, -length * i / max(n - 1, 1), z) for i in range(n)]


def v3f_array(points):
    a = imath.V3fArray(len(points))
    for i, p in enumerate(points):
        a[i] = imath.V3f(*p)
    return a


def int_array(values):
    a = imath.IntArray(len(values))
    for i, v in enumerate(values):
        a[i] = v
    return a


def float_array(values):
    a = imath.FloatArray(len(values))
    for i, v in enumerate(values):
        a[i] = v
    return a


def add_curves(parent, name, counts, points, kind, basis, widths=None, scope=None):
    obj = AbcGeom.OCurves(parent, name)
    width = AbcGeom.OFloatGeomParamSample()
    if widths is not None:
        width = AbcGeom.OFloatGeomParamSample(float_array(widths), scope)
    sample = AbcGeom.OCurvesSchemaSample(v3f_array(points), int_array(counts), kind,
                                         AbcGeom.CurvePeriodicity.kNonPeriodic, width)
    sample.setBasis(basis)
    obj.getSchema().set(sample)
    return obj


def write_groom():
    archive = Abc.OArchive(path("groom.abc"), True)
    top = archive.getTop()
    groom = AbcGeom.OXform(top, "groom")
    xs = AbcGeom.XformSample()
    xs.setTranslation(imath.V3d(1, 2, 3))
    xs.setYRotation(90.0)
    xs.setScale(imath.V3d(2, 2, 2))
    groom.getSchema().set(xs)

    pts = strand(0, 0, 3) + strand(0.5, 0, 4, 1.5, 0.3) + strand(1, 0, 2)
    strands = add_curves(groom, "strands", [3, 4, 2], pts, AbcGeom.CurveType.kLinear,
                         AbcGeom.BasisType.kNoBasis, [0.01 * (i + 1) for i in range(9)],
                         AbcGeom.GeometryScope.kVertexScope)
    arb = strands.getSchema().getArbGeomParams()
    color = AbcGeom.OC3fGeomParam(arb, "groom_color", False, AbcGeom.GeometryScope.kVertexScope, 1)
    colors = imath.C3fArray(9)
    for i in range(9):
        colors[i] = imath.Color3f(0.1 * i, 0.2, 0.9 - 0.1 * i)
    color.set(AbcGeom.OC3fGeomParamSample(colors, AbcGeom.GeometryScope.kVertexScope))
    uv = AbcGeom.OV2fGeomParam(arb, "groom_root_uv", False, AbcGeom.GeometryScope.kUniformScope, 1)
    uvs = imath.V2fArray(3)
    for i in range(3):
        uvs[i] = imath.V2f(0.25 * i, 0.5)
    uv.set(AbcGeom.OV2fGeomParamSample(uvs, AbcGeom.GeometryScope.kUniformScope))
    guide = AbcGeom.OInt32GeomParam(arb, "groom_guide", False, AbcGeom.GeometryScope.kUniformScope, 1)
    guide.set(AbcGeom.OInt32GeomParamSample(int_array([0, 0, 1]), AbcGeom.GeometryScope.kUniformScope))

    inner = AbcGeom.OXform(groom, "inner")
    xi = AbcGeom.XformSample()
    xi.setTranslation(imath.V3d(0, -1, 0))
    inner.getSchema().set(xi)
    add_curves(inner, "bspline", [4, 5], strand(0, 1, 4, 1, 0.5) + strand(1, 1, 5, 2, -0.5),
               AbcGeom.CurveType.kCubic, AbcGeom.BasisType.kBsplineBasis, [0.02],
               AbcGeom.GeometryScope.kConstantScope)
    add_curves(top, "catmull", [5], strand(3, 0, 5, 1, 0.7), AbcGeom.CurveType.kCubic,
               AbcGeom.BasisType.kCatmullromBasis, [0.03], AbcGeom.GeometryScope.kUniformScope)
    add_curves(top, "bezier", [4, 7], strand(5, 0, 4, 1, 0.2) + strand(6, 0, 7, 2, 0.9),
               AbcGeom.CurveType.kCubic, AbcGeom.BasisType.kBezierBasis)


def walk(obj, parent_matrix, out):
    """Every ICurves below obj with its world matrix (row vectors: p * local * parent)."""
    for i in range(obj.getNumChildren()):
        child = obj.getChild(i)
        matrix = parent_matrix
        if AbcGeom.IXform.matches(child.getHeader()):
            local = AbcGeom.IXform(child, Abc.WrapExistingFlag.kWrapExisting).getSchema().getValue()
            matrix = local.getMatrix() * parent_matrix
        if AbcGeom.ICurves.matches(child.getHeader()):
            out.append((AbcGeom.ICurves(child, Abc.WrapExistingFlag.kWrapExisting), matrix))
        walk(child, matrix, out)


def describe(file_name):
    archive = Abc.IArchive(path(file_name))
    found = []
    identity = imath.M44d()
    walk(archive.getTop(), identity, found)
    points, thickness, objects, strands, guides = [], [], [], 0, 0
    for curves, matrix in found:
        objects.append(curves.getFullName())
        schema = curves.getSchema()
        sample = schema.getValue()
        pos = [(p[0], p[1], p[2]) for p in sample.getPositions()]
        counts = list(sample.getCurvesNumVertices())
        kind = sample.getType()
        basis = BASES.get(sample.getBasis())
        is_guide = [0] * len(counts)
        arb = schema.getArbGeomParams()
        if arb.valid() and arb.getPropertyHeader("groom_guide") is not None:
            param = AbcGeom.IInt32GeomParam(arb, "groom_guide")
            is_guide = list(param.getExpandedValue().getVals())
        widths = None
        scope = None
        wparam = schema.getWidthsParam()
        if wparam.valid():
            wsample = wparam.getExpandedValue()
            widths = list(wsample.getVals())
            scope = wsample.getScope()
        scale = abs(det3(matrix)) ** (1.0 / 3.0)
        start = 0
        for i, n in enumerate(counts):
            ctrl = pos[start:start + n]
            if is_guide[i]:
                guides += 1
                start += n
                continue
            tess = ctrl if kind == AbcGeom.CurveType.kLinear else curve_eval.cubic(ctrl, basis, "nonperiodic", SEGMENTS)
            for p in tess:
                w = imath.V3d(*p) * matrix
                points.append((w[0], w[1], w[2]))
            strands += 1
            if widths is not None:
                if scope == AbcGeom.GeometryScope.kVertexScope:
                    ws = widths[start:start + n]
                    if kind != AbcGeom.CurveType.kLinear:
                        ws = curve_eval.cubic_scalar(ws, basis, "nonperiodic", SEGMENTS)
                elif scope == AbcGeom.GeometryScope.kUniformScope:
                    ws = [widths[i]]
                else:
                    ws = [widths[0]]
                thickness += [x * scale for x in ws]
            start += n
    lo, hi = curve_eval.bounds(points)
    return {
        "objects": objects,
        "strands": strands,
        "guides_skipped": guides,
        "vertices": len(points),
        "bbox_min": lo,
        "bbox_max": hi,
        "thickness_min": min(thickness),
        "thickness_max": max(thickness),
        "has_color": True,
        "has_strand_uv": True,
    }


def det3(m):
    a = [[m[r][c] for c in range(3)] for r in range(3)]
    return (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))


def hostile():
    with open(path("hdf5.abc"), "wb") as f:
        f.write(b"\x89HDF\r\n\x1a\n" + bytes(504))
    with open(path("groom.abc"), "rb") as f:
        data = f.read()
    with open(path("truncated.abc"), "wb") as f:
        f.write(data[:200])
    with open(path("bad_magic.abc"), "wb") as f:
        f.write(b"Ogxwa" + data[5:])


def main():
    write_groom()
    expected = {"groom.abc": describe("groom.abc")}
    hostile()
    expected["_rule"] = ("cubic curves: %d segments per span; curves with groom_guide != 0 are "
                         "skipped; widths scaled by the cube root of the world 3x3 determinant"
                         % SEGMENTS)
    with open(path("abc_expected.json"), "w") as f:
        json.dump(expected, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
