#!/usr/bin/env python3
"""Write the rich USD seeds of the read_usd fuzz target with Pixar's USD (`pip install usd-core`).

The groom seeds (groom.usd[acz]) hold curves and a mesh only, so from them the fuzzer rarely
reaches the parts of openusd's readers that other value types use. rich.usd[acz] hold one of
nearly every kind of value a crate file stores: nested dictionaries (customLayerData,
customData), time samples, references, payloads, inherits, specializes, variant sets and
selections, token / string / path / int list ops (apiSchemas, relationships), arrays that the
crate writer compresses (long int arrays; float arrays of few distinct values, which it stores as
a lookup table), half, double, quaternion and matrix values, asset paths, strings, and curves
whose points are time-sampled.

Each seed is the target's input: the first byte picks the flavour (0 usda, 1 usdc, 2 usdz).
Run: python3 fuzz/seeds/make_usd_seeds.py
"""

import os
import pathlib
import tempfile
import zipfile

from pxr import Gf, Sdf, Usd, UsdGeom, Vt

HERE = pathlib.Path(__file__).resolve().parent / "read_usd"


def build(stage):
    layer = stage.GetRootLayer()
    layer.customLayerData = {"tool": "tress seeds", "nested": {"depth": 2, "list": Vt.IntArray([1, 2, 3])}}
    stage.SetStartTimeCode(1)
    stage.SetEndTimeCode(3)
    stage.SetTimeCodesPerSecond(24)
    stage.SetMetadata("comment", "a fuzz seed")

    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    world.AddTranslateOp().Set(Gf.Vec3d(1, 2, 3))
    world.AddRotateXYZOp().Set(Gf.Vec3f(10, 20, 30))
    world.AddScaleOp(UsdGeom.XformOp.PrecisionHalf).Set(Gf.Vec3h(1, 1, 1))
    world.GetPrim().SetCustomDataByKey("note", "custom")
    world.GetPrim().SetAssetInfoByKey("identifier", Sdf.AssetPath("asset.usd"))

    proto = stage.DefinePrim("/World/Proto", "Xform")
    proto.CreateAttribute("tress:label", Sdf.ValueTypeNames.String).Set("proto")
    klass = stage.CreateClassPrim("/_class")
    klass.CreateAttribute("tress:flag", Sdf.ValueTypeNames.Bool).Set(True)

    user = stage.DefinePrim("/World/User", "Xform")
    user.GetReferences().AddInternalReference("/World/Proto")
    user.GetPayloads().AddInternalPayload("/World/Proto")
    user.GetInherits().AddInherit("/_class")
    user.GetSpecializes().AddSpecialize("/World/Proto")
    user.ApplyAPI(UsdGeom.MotionAPI)
    vset = user.GetVariantSets().AddVariantSet("look")
    for name in ("short", "long"):
        vset.AddVariant(name)
    vset.SetVariantSelection("short")
    with vset.GetVariantEditContext():
        user.CreateAttribute("tress:length", Sdf.ValueTypeNames.Float).Set(2.5)
    rel = user.CreateRelationship("tress:targets")
    rel.AddTarget("/World/Proto")
    rel.AddTarget("/World/Hair")

    curves = UsdGeom.BasisCurves.Define(stage, "/World/Hair")
    curves.CreateTypeAttr("cubic")
    curves.CreateBasisAttr("catmullRom")
    curves.CreateWrapAttr("pinned")
    counts = Vt.IntArray([4, 5, 4, 6])
    curves.CreateCurveVertexCountsAttr(counts)
    points = [Gf.Vec3f(i * 0.1, (i % 5) * 0.3, 0.2 * (i % 3)) for i in range(19)]
    attr = curves.CreatePointsAttr()
    for t in (1, 2, 3):
        attr.Set(Vt.Vec3fArray([p + Gf.Vec3f(0, 0.1 * t, 0) for p in points]), Usd.TimeCode(t))
    curves.CreateWidthsAttr(Vt.FloatArray([0.1, 0.2] * 9 + [0.1]))
    curves.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
    primvars = UsdGeom.PrimvarsAPI(curves)
    color = primvars.CreatePrimvar("displayColor", Sdf.ValueTypeNames.Color3fArray, UsdGeom.Tokens.uniform)
    color.Set(Vt.Vec3fArray([Gf.Vec3f(0.3, 0.2, 0.1), Gf.Vec3f(0.5, 0.4, 0.3)]))
    color.SetIndices(Vt.IntArray([0, 1, 0, 1]))
    primvars.CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.uniform).Set(
        Vt.Vec2fArray([Gf.Vec2f(0.1 * i, 0.2) for i in range(4)])
    )
    prim = curves.GetPrim()
    prim.CreateAttribute("tress:ints", Sdf.ValueTypeNames.IntArray).Set(Vt.IntArray(list(range(0, 400, 3))))
    prim.CreateAttribute("tress:int64s", Sdf.ValueTypeNames.Int64Array).Set(Vt.Int64Array([1 << 40, 5, 5, 5, 7, 9]))
    prim.CreateAttribute("tress:lookup", Sdf.ValueTypeNames.FloatArray).Set(Vt.FloatArray([0.5, 1.5, 0.5, 2.5] * 40))
    prim.CreateAttribute("tress:doubles", Sdf.ValueTypeNames.DoubleArray).Set(Vt.DoubleArray([0.25 * i for i in range(64)]))
    prim.CreateAttribute("tress:halves", Sdf.ValueTypeNames.HalfArray).Set(Vt.HalfArray([0.5, 1.0, 1.5, 2.0, 2.5]))
    prim.CreateAttribute("tress:bools", Sdf.ValueTypeNames.BoolArray).Set(Vt.BoolArray([True, False, True]))
    prim.CreateAttribute("tress:strings", Sdf.ValueTypeNames.StringArray).Set(Vt.StringArray(["a", "bc", "def"]))
    prim.CreateAttribute("tress:tokens", Sdf.ValueTypeNames.TokenArray).Set(Vt.TokenArray(["x", "y"]))
    prim.CreateAttribute("tress:asset", Sdf.ValueTypeNames.Asset).Set(Sdf.AssetPath("textures/hair.png"))
    prim.CreateAttribute("tress:assets", Sdf.ValueTypeNames.AssetArray).Set(Sdf.AssetPathArray(["a.png", "b.png"]))
    prim.CreateAttribute("tress:quat", Sdf.ValueTypeNames.Quatf).Set(Gf.Quatf(1, 0, 0, 0))
    prim.CreateAttribute("tress:quatd", Sdf.ValueTypeNames.Quatd).Set(Gf.Quatd(0.5, 0.5, 0.5, 0.5))
    prim.CreateAttribute("tress:matrix", Sdf.ValueTypeNames.Matrix4d).Set(Gf.Matrix4d(2.0))
    prim.CreateAttribute("tress:matrices", Sdf.ValueTypeNames.Matrix4dArray).Set(
        Vt.Matrix4dArray([Gf.Matrix4d(1.0), Gf.Matrix4d().SetTranslate(Gf.Vec3d(1, 2, 3))])
    )
    prim.CreateAttribute("tress:uchar", Sdf.ValueTypeNames.UChar).Set(7)
    prim.CreateAttribute("tress:blocked", Sdf.ValueTypeNames.Float).Block()
    timed = prim.CreateAttribute("tress:timed", Sdf.ValueTypeNames.Double)
    for t, v in ((1, 0.0), (2, 0.5), (3, 1.0)):
        timed.Set(v, Usd.TimeCode(t))
    timed.SetCustomData({"units": "cm", "range": Gf.Vec2d(0, 1)})
    prim.SetMetadata("kind", "component")
    prim.SetDocumentation("rich seed curves")

    mesh = UsdGeom.Mesh.Define(stage, "/World/Head")
    mesh.CreatePointsAttr(Vt.Vec3fArray([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray([4]))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray([0, 1, 2, 3]))
    mesh.CreateOrientationAttr(UsdGeom.Tokens.leftHanded)


def main():
    HERE.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for pick, ext in enumerate(("usda", "usdc")):
            name = os.path.join(tmp, f"rich.{ext}")
            stage = Usd.Stage.CreateNew(name)
            build(stage)
            stage.GetRootLayer().Save()
            data = pathlib.Path(name).read_bytes()
            (HERE / f"rich.{ext}.seed").write_bytes(bytes([pick]) + data)
        # A package holding the crate file, stored (USDZ packages are uncompressed zips whose
        # files are 64-byte aligned; Python's zipfile does not align, which openusd accepts).
        usdz = os.path.join(tmp, "rich.usdz")
        with zipfile.ZipFile(usdz, "w", zipfile.ZIP_STORED) as z:
            z.write(os.path.join(tmp, "rich.usdc"), "rich.usdc")
        (HERE / "rich.usdz.seed").write_bytes(bytes([2]) + pathlib.Path(usdz).read_bytes())


if __name__ == "__main__":
    main()
