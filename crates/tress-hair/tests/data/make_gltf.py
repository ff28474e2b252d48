"""Write the glTF test meshes with pygltflib (`pip install pygltflib`) and state what they must
read as in gltf_expected.json (read by crates/tress-hair/tests/formats_mesh.rs).

Run from this folder: `python3 make_gltf.py`. Files (a unit cube, 8 vertices, 12 triangles):
- cube.gltf + cube.bin: the cube below a node translated by (0, 2, 0) and scaled by 0.5.
- cube.glb: the same as one binary file.
- cube_embedded.gltf: the buffer as a base64 data URI, no node transform.
- cube_lying.glb: cube.glb without the node transform, its buffer's byteLength claiming 999 bytes
  (it has 168).
"""

import json
import os
import struct

import pygltflib

HERE = os.path.dirname(os.path.abspath(__file__))
CORNERS = [(x, y, z) for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)]
FACES = [0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4,
         1, 5, 7, 1, 7, 3]


def cube(translation=None, scale=None):
    positions = b"".join(struct.pack("<3f", *p) for p in CORNERS)
    indices = b"".join(struct.pack("<H", i) for i in FACES)
    blob = indices + positions
    node = pygltflib.Node(mesh=0)
    if translation:
        node.translation = translation
    if scale:
        node.scale = scale
    g = pygltflib.GLTF2(
        scene=0,
        scenes=[pygltflib.Scene(nodes=[0])],
        nodes=[node],
        meshes=[pygltflib.Mesh(primitives=[pygltflib.Primitive(
            attributes=pygltflib.Attributes(POSITION=1), indices=0)])],
        accessors=[
            pygltflib.Accessor(bufferView=0, componentType=pygltflib.UNSIGNED_SHORT,
                               count=len(FACES), type=pygltflib.SCALAR),
            pygltflib.Accessor(bufferView=1, componentType=pygltflib.FLOAT, count=len(CORNERS),
                               type=pygltflib.VEC3, min=[-1, -1, -1], max=[1, 1, 1]),
        ],
        bufferViews=[
            pygltflib.BufferView(buffer=0, byteOffset=0, byteLength=len(indices),
                                 target=pygltflib.ELEMENT_ARRAY_BUFFER),
            pygltflib.BufferView(buffer=0, byteOffset=len(indices), byteLength=len(positions),
                                 target=pygltflib.ARRAY_BUFFER),
        ],
        buffers=[pygltflib.Buffer(byteLength=len(blob))],
    )
    g.set_binary_blob(blob)
    return g


def main():
    g = cube([0.0, 2.0, 0.0], [0.5, 0.5, 0.5])
    g.save_binary(os.path.join(HERE, "cube.glb"))
    g = cube([0.0, 2.0, 0.0], [0.5, 0.5, 0.5])
    with open(os.path.join(HERE, "cube.bin"), "wb") as f:
        f.write(g.binary_blob())
    g.buffers[0].uri = "cube.bin"
    g.set_binary_blob(None)
    g.save_json(os.path.join(HERE, "cube.gltf"))
    g = cube()
    g.convert_buffers(pygltflib.BufferFormat.DATAURI)
    g.save(os.path.join(HERE, "cube_embedded.gltf"))
    # pygltflib recomputes byteLength on save: make the lie in the written JSON chunk (same length).
    cube().save_binary(os.path.join(HERE, "cube_lying.glb"))
    with open(os.path.join(HERE, "cube_lying.glb"), "rb") as f:
        glb = f.read()
    glb = glb.replace(b'"byteLength":168}]', b'"byteLength":999}]', 1)
    assert b'"byteLength":999}]' in glb
    with open(os.path.join(HERE, "cube_lying.glb"), "wb") as f:
        f.write(glb)
    moved = {"triangles": 12, "vertices": 8, "min": [-0.5, 1.5, -0.5], "max": [0.5, 2.5, 0.5]}
    expected = {
        "cube.glb": moved,
        "cube.gltf": moved,
        "cube_embedded.gltf": {"triangles": 12, "vertices": 8, "min": [-1, -1, -1], "max": [1, 1, 1]},
    }
    with open(os.path.join(HERE, "gltf_expected.json"), "w") as f:
        json.dump(expected, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
