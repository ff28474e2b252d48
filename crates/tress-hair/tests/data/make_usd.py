"""Write the USD test files with Pixar's own USD (`pip install usd-core`) and state what each must
read as in usd_expected.json (read by crates/tress-hair/tests/formats_usd.rs).

Run from this folder: `python3 make_usd.py`. The generated files are committed, so the tests need
no Python. What every file must read as is computed here with USD's own API
(`ComputeLocalToWorldTransform`) and, for cubic and NURBS curves, with curve_eval.py's reference
evaluation of tress's documented tessellation rule (4 segments per span, the default).

Files:
- groom.usda / groom.usdc / groom.usdz: three linear BasisCurves prims (mixed vertex counts; widths
  per vertex, constant and per curve; displayColor per vertex, constant, none), one of them below
  a transformed Xform (translate, rotateY, scale), and a Mesh head (a cube: 12 triangles).
- cubic.usda: bezier, bspline (nonperiodic and pinned) and catmullRom (nonperiodic and pinned)
  curves; widths per vertex, varying, constant and per curve.
- nurbs.usda: NurbsCurves, degree 3 (order 4), clamped knots, one with an interior knot.
- cycle_a.usda / cycle_b.usda: each references the other (a composition cycle).
- self_ref.usda: a prim that references itself inside its own layer.
- truncated.usdc: the first 300 bytes of groom.usdc. bad_magic.usdc: groom.usdc with its magic
  changed.
"""

import json
import os

from pxr import Gf, Sdf, Usd, UsdGeom, UsdUtils, Vt

import curve_eval

SEGMENTS = 4
HERE = os.path.dirname(os.path.abspath(__file__))


def path(name):
    return os.path.join(HERE, name)


def world_points(prim, points):
    m = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode.Default())
    return [tuple(m.Transform(Gf.Vec3d(*p))) for p in points], m


def width_scale(m):
    return abs(m.GetDeterminant3()) ** (1.0 / 3.0)


def curves(stage, prim_path, counts, points, kind="linear", basis=None, wrap=None):
    c = UsdGeom.BasisCurves.Define(stage, prim_path)
    c.CreateTypeAttr(kind)
    if basis:
        c.CreateBasisAttr(basis)
    if wrap:
        c.CreateWrapAttr(wrap)
    c.CreateCurveVertexCountsAttr(Vt.IntArray(counts))
    c.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(*p) for p in points]))
    return c


def set_widths(c, widths, interpolation):
    c.CreateWidthsAttr(Vt.FloatArray(widths))
    c.SetWidthsInterpolation(interpolation)


def strand(x, z, n, length=1.0, bend=0.0):
    """n points of a strand rooted at (x, 0, z) growing down -y, bending towards +x."""
    return [(x + bend * (i / max(n - 1, 1)) ** 2, -length * i / max(n - 1, 1), z) for i in range(n)]


def groom_stage(file_name):
    stage = Usd.Stage.CreateNew(path(file_name))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.Xform.Define(stage, "/World")

    pts = strand(0, 0, 2) + strand(0.5, 0, 3, bend=0.2) + strand(1, 0.5, 5, 2.0, 0.5)
    lin = curves(stage, "/World/Linear", [2, 3, 5], pts)
    set_widths(lin, [0.01 * (i + 1) for i in range(10)], UsdGeom.Tokens.vertex)
    color = lin.CreateDisplayColorPrimvar(UsdGeom.Tokens.vertex)
    color.Set(Vt.Vec3fArray([Gf.Vec3f(0.1 * i, 0.5, 1 - 0.1 * i) for i in range(10)]))

    const = curves(stage, "/World/Constant", [4], strand(-1, -1, 4, 1.5, -0.3))
    set_widths(const, [0.05], UsdGeom.Tokens.constant)
    const.CreateDisplayColorPrimvar(UsdGeom.Tokens.constant).Set(
        Vt.Vec3fArray([Gf.Vec3f(0.8, 0.4, 0.2)]))

    moved = UsdGeom.Xform.Define(stage, "/World/Moved")
    moved.AddTranslateOp().Set(Gf.Vec3d(10, 0, 0))
    moved.AddRotateYOp().Set(90.0)
    moved.AddScaleOp().Set(Gf.Vec3f(2, 2, 2))
    inner = curves(stage, "/World/Moved/Curves", [3, 3],
                   strand(0, 0, 3) + strand(1, 0, 3, 0.5))
    set_widths(inner, [0.1, 0.2], UsdGeom.Tokens.uniform)

    head = UsdGeom.Mesh.Define(stage, "/World/Head")
    cube = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
    head.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(x, y + 2, z) for x, y, z in cube]))
    head.CreateFaceVertexCountsAttr(Vt.IntArray([4] * 6))
    head.CreateFaceVertexIndicesAttr(Vt.IntArray(
        [0, 1, 3, 2, 4, 6, 7, 5, 0, 4, 5, 1, 2, 3, 7, 6, 0, 2, 6, 4, 1, 5, 7, 3]))
    stage.GetRootLayer().Save()
    return stage


def curve_prims(stage):
    return [p for p in stage.Traverse() if p.IsA(UsdGeom.BasisCurves) or p.IsA(UsdGeom.NurbsCurves)]


def primvar_per_curve(values, interpolation, counts, index, varying_count):
    """The values of curve `index` for a primvar of the given interpolation."""
    if interpolation == "constant":
        return ("constant", values[0])
    if interpolation == "uniform":
        return ("constant", values[index])
    start = sum(counts[:index]) if interpolation == "vertex" else sum(varying_count[:index])
    n = counts[index] if interpolation == "vertex" else varying_count[index]
    return (interpolation, values[start:start + n])


def describe(stage, file_name):
    """What a reader following tress's rules must get from the stage."""
    all_points, thickness, prims, has_color, strands = [], [], [], False, 0
    for prim in curve_prims(stage):
        prims.append(str(prim.GetPath()))
        c = UsdGeom.Curves(prim)
        counts = list(c.GetCurveVertexCountsAttr().Get())
        pts = [tuple(p) for p in c.GetPointsAttr().Get()]
        widths = c.GetWidthsAttr().Get()
        interp = c.GetWidthsInterpolation()
        has_color |= UsdGeom.PrimvarsAPI(prim).GetPrimvar("displayColor").HasAuthoredValue()
        _, m = world_points(prim, [])
        if prim.IsA(UsdGeom.NurbsCurves):
            n = UsdGeom.NurbsCurves(prim)
            orders, knots = list(n.GetOrderAttr().Get()), list(n.GetKnotsAttr().Get())
            k0 = 0
            start = 0
            for i, cnt in enumerate(counts):
                kn = knots[k0:k0 + cnt + orders[i]]
                k0 += cnt + orders[i]
                all_points += world_points(prim, curve_eval.nurbs(pts[start:start + cnt],
                                                                  orders[i], kn, SEGMENTS))[0]
                start += cnt
            thickness += [w * width_scale(m) for w in widths]
            strands += len(counts)
            continue
        b = UsdGeom.BasisCurves(prim)
        kind = b.GetTypeAttr().Get()
        basis = b.GetBasisAttr().Get()
        wrap = b.GetWrapAttr().Get()
        start = 0
        varying = [len(curve_eval.spans(cnt, basis, wrap)) + 1 if kind == "cubic" else cnt
                   for cnt in counts]
        for i, cnt in enumerate(counts):
            ctrl = pts[start:start + cnt]
            start += cnt
            if kind == "linear":
                out = ctrl
            else:
                out = curve_eval.cubic(ctrl, basis, wrap, SEGMENTS)
            all_points += world_points(prim, out)[0]
            strands += 1
            if widths is None:
                continue
            mode, w = primvar_per_curve(list(widths), interp, counts, i, varying)
            if mode == "vertex" and kind == "cubic":
                w = curve_eval.cubic_scalar(w, basis, wrap, SEGMENTS)
            elif mode == "varying" and kind == "cubic":
                w = [w[si] + (w[si + 1] - w[si]) * k / SEGMENTS
                     for si in range(len(w) - 1) for k in range(0 if si == 0 else 1, SEGMENTS + 1)]
            elif mode == "constant":
                w = [w]
            thickness += [x * width_scale(m) for x in w]
    lo, hi = curve_eval.bounds(all_points)
    out = {
        "prims": prims,
        "strands": strands,
        "vertices": len(all_points),
        "bbox_min": lo,
        "bbox_max": hi,
        "thickness_min": min(thickness),
        "thickness_max": max(thickness),
        "has_color": has_color,
    }
    meshes = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    if meshes:
        mesh_pts, tris = [], 0
        for prim in meshes:
            mesh = UsdGeom.Mesh(prim)
            mesh_pts += world_points(prim, [tuple(p) for p in mesh.GetPointsAttr().Get()])[0]
            tris += sum(n - 2 for n in mesh.GetFaceVertexCountsAttr().Get())
        mlo, mhi = curve_eval.bounds(mesh_pts)
        out.update(mesh_triangles=tris, mesh_vertices=len(mesh_pts), mesh_min=mlo, mesh_max=mhi)
    return out


def cubic_stage():
    stage = Usd.Stage.CreateNew(path("cubic.usda"))
    UsdGeom.Scope.Define(stage, "/Cubic")
    bez = curves(stage, "/Cubic/Bezier", [4, 7], strand(0, 0, 4, 1, 0.4) + strand(1, 0, 7, 2, -0.6),
                 "cubic", "bezier", "nonperiodic")
    set_widths(bez, [0.02 + 0.01 * i for i in range(11)], UsdGeom.Tokens.vertex)
    bsp = curves(stage, "/Cubic/BsplinePinned", [4, 6], strand(2, 0, 4, 1, 0.3) + strand(3, 0, 6, 1.5, 0.8),
                 "cubic", "bspline", "pinned")
    # varying: spans + 1 values per curve (pinned: 3 + 1 and 5 + 1)
    set_widths(bsp, [0.1, 0.08, 0.06, 0.04, 0.1, 0.09, 0.08, 0.07, 0.06, 0.05], UsdGeom.Tokens.varying)
    bs = curves(stage, "/Cubic/Bspline", [5], strand(4, 1, 5, 1, 1.0), "cubic", "bspline", "nonperiodic")
    set_widths(bs, [0.03], UsdGeom.Tokens.constant)
    cr = curves(stage, "/Cubic/CatmullRom", [5], strand(5, 0, 5, 1.2, -0.5), "cubic", "catmullRom",
                "nonperiodic")
    cr.CreateDisplayColorPrimvar(UsdGeom.Tokens.constant).Set(Vt.Vec3fArray([Gf.Vec3f(1, 0, 0)]))
    crp = curves(stage, "/Cubic/CatmullRomPinned", [3, 4], strand(6, 0, 3, 1, 0.5) + strand(7, 0, 4, 1, -0.5),
                 "cubic", "catmullRom", "pinned")
    set_widths(crp, [0.04, 0.07], UsdGeom.Tokens.uniform)
    stage.GetRootLayer().Save()
    return stage


def nurbs_stage():
    stage = Usd.Stage.CreateNew(path("nurbs.usda"))
    n = UsdGeom.NurbsCurves.Define(stage, "/Nurbs")
    pts = strand(0, 0, 4, 1, 0.5) + strand(1, 0, 6, 2, -1.0)
    n.CreateCurveVertexCountsAttr(Vt.IntArray([4, 6]))
    n.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(*p) for p in pts]))
    n.CreateOrderAttr(Vt.IntArray([4, 4]))
    n.CreateKnotsAttr(Vt.DoubleArray([0, 0, 0, 0, 1, 1, 1, 1] + [0, 0, 0, 0, 1, 2, 3, 3, 3, 3]))
    n.CreateWidthsAttr(Vt.FloatArray([0.02]))
    n.SetWidthsInterpolation(UsdGeom.Tokens.constant)
    stage.GetRootLayer().Save()
    return stage


def hostile():
    with open(path("cycle_a.usda"), "w") as f:
        f.write('#usda 1.0\n\ndef Xform "A" (\n    prepend references = @./cycle_b.usda@</B>\n)\n{\n}\n')
    with open(path("cycle_b.usda"), "w") as f:
        f.write('#usda 1.0\n\ndef Xform "B" (\n    prepend references = @./cycle_a.usda@</A>\n)\n{\n}\n')
    with open(path("self_ref.usda"), "w") as f:
        f.write('#usda 1.0\n\ndef Xform "Loop" (\n    prepend references = </Loop>\n)\n{\n}\n')
    with open(path("groom.usdc"), "rb") as f:
        data = f.read()
    with open(path("truncated.usdc"), "wb") as f:
        f.write(data[:300])
    with open(path("bad_magic.usdc"), "wb") as f:
        f.write(b"PXR-XXXX" + data[8:])


def main():
    expected = {}
    stage = groom_stage("groom.usda")
    expected["groom.usda"] = describe(stage, "groom.usda")
    stage.GetRootLayer().Export(path("groom.usdc"))
    expected["groom.usdc"] = describe(Usd.Stage.Open(path("groom.usdc")), "groom.usdc")
    if os.path.exists(path("groom.usdz")):
        os.remove(path("groom.usdz"))
    assert UsdUtils.CreateNewUsdzPackage(Sdf.AssetPath(path("groom.usdc")), path("groom.usdz"))
    expected["groom.usdz"] = describe(Usd.Stage.Open(path("groom.usdz")), "groom.usdz")
    expected["cubic.usda"] = describe(cubic_stage(), "cubic.usda")
    expected["nurbs.usda"] = describe(nurbs_stage(), "nurbs.usda")
    hostile()
    expected["_rule"] = ("cubic and NURBS curves: %d segments per span; widths are diameters, "
                         "scaled by the cube root of the world matrix's 3x3 determinant" % SEGMENTS)
    with open(path("usd_expected.json"), "w") as f:
        json.dump(expected, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
