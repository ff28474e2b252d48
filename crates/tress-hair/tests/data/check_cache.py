"""Check animated hair caches written by `tress simulate` with the outside world's readers.

    tress simulate -o /tmp/c.abc --frames 12 --motion turn
    tress simulate -o /tmp/c.usdc --frames 12 --motion turn
    tress simulate -o /tmp/c.usda --frames 12 --motion turn
    python3 crates/tress-hair/tests/data/check_cache.py /tmp/c.abc /tmp/c.usdc /tmp/c.usda

For each cache, the frames are read with the format's own library (the Alembic library through
`alembic3d` for `.abc`, Pixar's `usd-core` for USD): the sample count, the frame rate, every
frame's points, and that the hair moves between frames. Then, when Blender is installed as a
Python module (`pip install bpy`), the cache is imported into Blender 5 (`wm.alembic_import`,
`wm.usd_import`) and every frame's evaluated curve points are compared with the library's
(in the curves' own space: Blender turns Alembic's Y-up into Z-up in the points, (x, y, z) ->
(x, -z, y), and USD's in the object's transform). Prints one line per check
and exits non-zero on the first failure. Not run by CI (it needs those packages); its result is
recorded in docs/simulation.md.
"""

import sys

import numpy as np


def fail(msg):
    print(f"FAIL: {msg}")
    sys.exit(1)


def read_abc(path):
    from alembic3d import Abc, AbcGeom

    archive = Abc.IArchive(path)
    found = []

    def walk(obj):
        for i in range(obj.getNumChildren()):
            child = obj.getChild(i)
            if AbcGeom.ICurves.matches(child.getHeader()):
                found.append(AbcGeom.ICurves(child, Abc.WrapExistingFlag.kWrapExisting))
            walk(child)

    walk(archive.getTop())
    if len(found) != 1:
        fail(f"{path}: {len(found)} curves objects, expected 1")
    schema = found[0].getSchema()
    ts = schema.getTimeSampling()
    n = schema.getNumSamples()
    frames = []
    for k in range(n):
        # A sample selected by its time (a bare int would be taken as seconds).
        sample = schema.getValue(Abc.ISampleSelector(ts.getSampleTime(k)))
        frames.append(np.array([tuple(p) for p in sample.getPositions()], dtype=np.float64))
    counts = list(schema.getValue().getCurvesNumVertices())
    fps = 1.0 / ts.getTimeSamplingType().getTimePerCycle()
    return frames, counts, fps


def read_usd(path):
    from pxr import Usd, UsdGeom

    stage = Usd.Stage.Open(path)
    prims = [p for p in stage.Traverse() if p.GetTypeName() == "BasisCurves"]
    if len(prims) != 1:
        fail(f"{path}: {len(prims)} BasisCurves prims, expected 1")
    curves = UsdGeom.BasisCurves(prims[0])
    attr = curves.GetPointsAttr()
    times = attr.GetTimeSamples()
    frames = [np.array(attr.Get(t), dtype=np.float64) for t in times]
    counts = list(curves.GetCurveVertexCountsAttr().Get())
    return frames, counts, stage.GetTimeCodesPerSecond()


def blender_frames(path, n):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path.endswith(".abc"):
        bpy.ops.wm.alembic_import(filepath=path)
    else:
        bpy.ops.wm.usd_import(filepath=path)
    objects = [o for o in bpy.data.objects if o.type == "CURVES"]
    if len(objects) != 1:
        fail(f"{path}: Blender made {len(objects)} curves objects, expected 1")
    obj = objects[0]
    scene = bpy.context.scene
    out = []
    for f in range(1, n + 1):
        scene.frame_set(f)
        data = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        out.append(np.array([p.position[:] for p in data.points], dtype=np.float64))
    return out, (scene.frame_start, scene.frame_end), bpy.app.version_string


def main(paths):
    try:
        import bpy  # noqa: F401

        have_blender = True
    except ImportError:
        have_blender = False
        print("Blender (bpy) is not installed: the library checks only")
    for path in paths:
        frames, counts, fps = read_abc(path) if path.endswith(".abc") else read_usd(path)
        n = len(frames)
        if n < 2:
            fail(f"{path}: {n} frames")
        if any(f.shape != frames[0].shape for f in frames) or frames[0].shape[0] != sum(counts):
            fail(f"{path}: frames of different sizes or not the curves' {sum(counts)} points")
        moved = max(np.abs(f - frames[0]).max() for f in frames)
        if moved <= 0.0:
            fail(f"{path}: the hair does not move")
        print(
            f"ok {path}: {n} frames at {fps:g} fps, {len(counts)} curves, "
            f"{frames[0].shape[0]} points, moves up to {moved:.3f}"
        )
        if not have_blender:
            continue
        seen, span, version = blender_frames(path, n)
        if span != (1, n):
            fail(f"{path}: Blender's frame range is {span}, not (1, {n})")
        worst = 0.0
        for k in range(n):
            want = frames[k]
            if path.endswith(".abc"):
                want = np.stack([want[:, 0], -want[:, 2], want[:, 1]], axis=1)
            if seen[k].shape != want.shape:
                fail(f"{path}: Blender has {seen[k].shape[0]} points at frame {k + 1}")
            worst = max(worst, float(np.abs(seen[k] - want).max()))
        scale = float(np.abs(frames[0]).max())
        if worst > 1e-5 * scale:
            fail(f"{path}: Blender's points differ from the library's by {worst}")
        print(
            f"ok {path}: Blender {version} plays frames 1-{n}, every frame's points "
            f"within {worst:.2e} of the library's"
        )


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(2)
    main(sys.argv[1:])
