"""A float-encoded Tessera GLB as a Blender mesh, read without Blender's glTF importer (Debian's
Blender 3.4 one fails on NumPy 1.24): vertices that the GLB repeats for a crease or a UV seam are
welded back into one Blender vertex by their bit-identical positions, and what made them differ
is kept per face corner (custom split normals, UVs); edges where the two sides' normals differ
are marked sharp."""
import json
import struct

import numpy as np


_COMPONENTS = {5123: np.uint16, 5125: np.uint32, 5126: np.float32}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}


def read_glb(glb: bytes) -> dict:
    """Positions, normals (Blender's Z-up), UVs (or None) and triangle indices of the GLB."""
    magic, _version, length = struct.unpack_from("<4sII", glb, 0)
    if magic != b"glTF" or length != len(glb):
        raise ValueError("not a GLB")
    json_length, _ = struct.unpack_from("<I4s", glb, 12)
    document = json.loads(glb[20:20 + json_length])
    bin_at = 20 + json_length + 8
    primitive = document["meshes"][0]["primitives"][0]

    def accessor(index):
        a = document["accessors"][index]
        view = document["bufferViews"][a["bufferView"]]
        dtype, width = np.dtype(_COMPONENTS[a["componentType"]]), _WIDTH[a["type"]]
        stride = view.get("byteStride", dtype.itemsize * width)
        start = bin_at + view.get("byteOffset", 0) + a.get("byteOffset", 0)
        return np.ndarray((a["count"], width), dtype, glb, start, (stride, dtype.itemsize)).copy()

    if "extensionsRequired" in document:
        raise ValueError("the GLB needs " + ", ".join(document["extensionsRequired"]) + "; ask for the float encoding")
    attributes = primitive["attributes"]
    # The node's translation: the mesh's origin when it lies far from the origin (docs/FAR-FROM-ORIGIN.md).
    y_up = accessor(attributes["POSITION"]).astype(np.float64) + np.array(document["nodes"][0].get("translation", [0, 0, 0]))
    normals = accessor(attributes["NORMAL"]).astype(np.float64)
    return {
        "positions": np.stack([y_up[:, 0], -y_up[:, 2], y_up[:, 1]], axis=1),  # from_y_up
        "normals": np.stack([normals[:, 0], -normals[:, 2], normals[:, 1]], axis=1),
        "uvs": accessor(attributes["TEXCOORD_0"]) if "TEXCOORD_0" in attributes else None,
        "indices": accessor(primitive["indices"]).reshape(-1).astype(np.int64),
    }


def build_mesh(bpy, name: str, glb: bytes):
    """A new Blender mesh datablock from the GLB."""
    data = read_glb(glb)
    positions, indices = data["positions"], data["indices"]
    # Weld: the GLB's copies repeat their vertex's position bit for bit.
    keys = np.ascontiguousarray(positions.astype(np.float32)).view(np.dtype((np.void, 12))).reshape(-1)
    _, weld = np.unique(keys, return_inverse=True)
    first = np.full(weld.max() + 1 if len(weld) else 0, len(weld), dtype=np.int64)
    np.minimum.at(first, weld, np.arange(len(weld)))
    vertices = positions[first]
    triangles = weld[indices].reshape(-1, 3)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices.tolist(), [], triangles.tolist())
    # Per face corner, what the GLB vertex of that corner carried (loops follow the triangles).
    corner_vertices = indices.reshape(-1, 3)
    loop_sources = np.zeros(len(mesh.loops), dtype=np.int64)
    for polygon in mesh.polygons:
        loop_sources[polygon.loop_start:polygon.loop_start + 3] = corner_vertices[polygon.index]
    if data["uvs"] is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        layer.data.foreach_set("uv", data["uvs"][loop_sources].reshape(-1))
    if hasattr(mesh, "use_auto_smooth"):  # Blender before 4.1: custom normals need it
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = 3.14159
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.normals_split_custom_set(data["normals"][loop_sources].tolist())
    _mark_sharp_edges(mesh, data["normals"], loop_sources)
    mesh.update()
    return mesh


def _mark_sharp_edges(mesh, normals, loop_sources) -> None:
    """An edge is sharp where the faces on it carry different normals at one of its ends."""
    ends = {}  # edge -> {vertex: the normals its faces' corners carry there}
    for polygon in mesh.polygons:
        loops = list(range(polygon.loop_start, polygon.loop_start + polygon.loop_total))
        for i, loop in enumerate(loops):
            edge = mesh.loops[loop].edge_index
            for corner in (loop, loops[(i + 1) % len(loops)]):
                normal = tuple(normals[loop_sources[corner]])
                ends.setdefault(edge, {}).setdefault(mesh.loops[corner].vertex_index, set()).add(normal)
    for edge, at in ends.items():
        if any(len(found) > 1 for found in at.values()):
            mesh.edges[edge].use_edge_sharp = True
