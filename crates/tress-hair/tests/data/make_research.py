"""Write small USC-HairSalon `.data` and CT2Hair `.bin` files with Python's struct module, from
the formats' published layouts, and state what they must read as in research_expected.json (read
by crates/tress-hair/tests/formats_research.rs).

Run from this folder: `python3 make_research.py`.
- salon.data: int32 strand count; per strand int32 vertex count and float32 xyz. 5 strands of 1,
  4, 1, 3 and 6 vertices: the two 1-vertex strands are skipped by tress (3 strands, 13 vertices).
- ct2hair.bin: int32 strand count; per strand int32 point count and per point 7 float32 (xyz and
  four more values, here 0.25, 0.5, 0.75, 1). 3 strands of 2, 5 and 3 points.
"""

import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def strand(x, z, n):
    return [(x + 0.1 * i * i, -0.5 * i, z - 0.05 * i) for i in range(n)]


def bounds(points):
    return [min(p[i] for p in points) for i in range(3)], [max(p[i] for p in points) for i in range(3)]


def main():
    salon = [strand(0, 0, 1), strand(1, 0, 4), strand(2, 1, 1), strand(3, 2, 3), strand(-1, -1, 6)]
    with open(os.path.join(HERE, "salon.data"), "wb") as f:
        f.write(struct.pack("<i", len(salon)))
        for s in salon:
            f.write(struct.pack("<i", len(s)))
            for p in s:
                f.write(struct.pack("<3f", *p))
    kept = [p for s in salon if len(s) > 1 for p in s]
    lo, hi = bounds(kept)
    expected = {"salon.data": {"strands": 3, "vertices": len(kept), "single_vertex_skipped": 2,
                               "bbox_min": lo, "bbox_max": hi}}
    ct = [strand(0, 3, 2), strand(1, 3, 5), strand(2, 3, 3)]
    with open(os.path.join(HERE, "ct2hair.bin"), "wb") as f:
        f.write(struct.pack("<i", len(ct)))
        for s in ct:
            f.write(struct.pack("<i", len(s)))
            for p in s:
                f.write(struct.pack("<7f", *p, 0.25, 0.5, 0.75, 1.0))
    pts = [p for s in ct for p in s]
    lo, hi = bounds(pts)
    expected["ct2hair.bin"] = {"strands": 3, "vertices": len(pts), "bbox_min": lo, "bbox_max": hi}
    with open(os.path.join(HERE, "research_expected.json"), "w") as f:
        json.dump(expected, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
