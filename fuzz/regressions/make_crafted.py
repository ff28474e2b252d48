#!/usr/bin/env python3
"""Write the hand-made regression inputs of issue 38 (the two crashes its fuzzing runs reported),
from committed valid files, so each one reaches exactly the panic that was reported:

- read_usd/token-index-past-table: crates/tress-hair/tests/data/groom.usdc with the curves prim's
  `typeName` (the inlined token `BasisCurves`) turned into a token stored in the file whose index is
  33,923,530,752 (openusd 0.6 `usdc/reader.rs:519`, `read_token`: "index out of bounds: the len is
  44 but the index is 33923530752", reached from tress's `metadata_decodes`).
- read_gltf/position-accessor-at-len: the cube GLB with its primitive's POSITION naming accessor 2
  of 2 (gltf-json 1.4.1 `mesh.rs:151`, `primitive_validate_hook`: "index out of bounds: the len is
  2 but the index is 2").

Each file is the fuzz target's input: for read_usd the first byte picks the flavour (1: usdc).
Needs `pip install lz4`. Run from anywhere: python3 fuzz/regressions/make_crafted.py
"""

import pathlib
import struct

import lz4.block

HERE = pathlib.Path(__file__).resolve().parent
DATA = HERE.parent.parent / "crates" / "tress-hair" / "tests" / "data"

TOKEN = 11
INLINED = 1 << 62
PAYLOAD = (1 << 48) - 1


def sections(crate: bytes):
    toc = struct.unpack_from("<Q", crate, 16)[0]
    count = struct.unpack_from("<Q", crate, toc)[0]
    for i in range(count):
        at = toc + 8 + 32 * i
        name = crate[at : at + 16].split(b"\0")[0].decode()
        start, size = struct.unpack_from("<QQ", crate, at + 16)
        yield name, at, start, size


def decode_ints(data: bytes, count: int) -> list:
    """Pixar's integer coding of 32-bit values (crate files' compressed integers)."""
    common = struct.unpack_from("<i", data, 0)[0]
    codes = (2 * count + 7) // 8
    at, prev, out = 4 + codes, 0, []
    for code in data[4 : 4 + codes]:
        for i in range(4):
            kind = (code >> (2 * i)) & 3
            if kind == 0:
                delta = common
            else:
                fmt, size = {1: ("<b", 1), 2: ("<h", 2), 3: ("<i", 4)}[kind]
                delta = struct.unpack_from(fmt, data, at)[0]
                at += size
            prev += delta
            out.append(prev)
    return out[:count]


def tokens(crate: bytes) -> list:
    (_, _, start, _) = next(s for s in sections(crate) if s[0] == "TOKENS")
    _, size, packed = struct.unpack_from("<QQQ", crate, start)
    block = crate[start + 24 : start + 24 + packed]
    return lz4.block.decompress(bytes(block[1:]), uncompressed_size=size).rstrip(b"\0").split(b"\0")


def token_index_past_table() -> bytes:
    crate = bytearray((DATA / "groom.usdc").read_bytes())
    names = tokens(crate)
    (_, entry, start, size) = next(s for s in sections(crate) if s[0] == "FIELDS")
    count = struct.unpack_from("<Q", crate, start)[0]
    at = start + 8
    indices_size = struct.unpack_from("<Q", crate, at)[0]
    indices = crate[at : at + 8 + indices_size]
    field_names = decode_ints(
        lz4.block.decompress(bytes(indices[9:]), uncompressed_size=4 + (2 * count + 7) // 8 + 4 * count),
        count,
    )
    at += 8 + indices_size
    reps_size = struct.unpack_from("<Q", crate, at)[0]
    reps_block = crate[at + 8 : at + 8 + reps_size]
    assert reps_block[0] == 0, "chunked LZ4"
    reps = bytearray(lz4.block.decompress(bytes(reps_block[1:]), uncompressed_size=8 * count))
    # The bytes the changed value points at: an index far past the 44-token table.
    index_at = len(crate)
    crate += struct.pack("<Q", 33923530752)
    for i in range(count):
        rep = struct.unpack_from("<Q", reps, 8 * i)[0]
        inlined_token = (rep >> 48) & 0xFF == TOKEN and rep & INLINED
        if names[field_names[i]] == b"typeName" and inlined_token and names[rep & 0xFFFFFFFF] == b"BasisCurves":
            rep = (TOKEN << 48) | index_at
            struct.pack_into("<Q", reps, 8 * i, rep)
            break
    else:
        raise SystemExit("groom.usdc has no BasisCurves typeName")
    packed = b"\0" + lz4.block.compress(bytes(reps), store_size=False)
    # A new FIELDS section at the end; the table of contents points at it.
    fields_at = len(crate)
    crate += struct.pack("<Q", count) + indices + struct.pack("<Q", len(packed)) + packed
    struct.pack_into("<QQ", crate, entry + 16, fields_at, len(crate) - fields_at)
    return bytes([1]) + bytes(crate)


def position_accessor_at_len() -> bytes:
    glb = (DATA / "cube.glb").read_bytes()
    json_len = struct.unpack_from("<I", glb, 12)[0]
    json = glb[20 : 20 + json_len]
    old = b'"POSITION":1'
    assert json.count(old) == 1, json
    json = json.replace(old, b'"POSITION":2')
    return glb[:20] + json + glb[20 + json_len :]


def main():
    (HERE / "read_usd").mkdir(exist_ok=True)
    (HERE / "read_gltf").mkdir(exist_ok=True)
    (HERE / "read_usd" / "token-index-past-table").write_bytes(token_index_past_table())
    (HERE / "read_gltf" / "position-accessor-at-len").write_bytes(position_accessor_at_len())


if __name__ == "__main__":
    main()
