"""A plain-Python reader of Cem Yuksel's .hair format, one strand at a time with ``struct``:
what hair-reconstruction repositories write for themselves. Used as an independent check of
``tress.load`` and as the baseline of ``bench/bench_load.py``.

Format (cemyuksel.com/research/hairmodels): a 128-byte header (b"HAIR", strands u32, points u32,
flags u32, default segments u32, default thickness f32, default transparency f32, default
colour 3 × f32, 88 bytes of text), then the arrays the flags name: segments (u16 per strand,
bit 0), points (3 × f32 per point, bit 1), thickness (f32, bit 2), transparency (f32, bit 3),
colour (3 × f32, bit 4).
"""

import struct


def read_hair(path):
    """Returns a list of strands, each a list of (x, y, z) tuples."""
    with open(path, "rb") as f:
        data = f.read()
    magic, strands, points, flags, default_segments = struct.unpack_from("<4sIIII", data, 0)
    if magic != b"HAIR":
        raise ValueError("not a .hair file")
    offset = 128
    if flags & 1:
        segments = [struct.unpack_from("<H", data, offset + 2 * i)[0] for i in range(strands)]
        offset += 2 * strands
    else:
        segments = [default_segments] * strands
    result = []
    for s in segments:
        strand = []
        for _ in range(s + 1):
            strand.append(struct.unpack_from("<3f", data, offset))
            offset += 12
        result.append(strand)
    return result
