"""A Tessera GLB (float, quantized or meshopt, docs/GLB.md) as a Blender mesh, read without
Blender's glTF importer (Debian's Blender 3.4 one fails on NumPy 1.24): meshopt views are decoded
by meshopt_decode.py, quantized positions and normals scaled back to floats, then vertices that
the GLB repeats for a crease or a UV seam are welded back into one Blender vertex by their
bit-identical positions, and what made them differ is kept per face corner (custom split normals,
UVs); edges where the two sides' normals differ are marked sharp."""
import json
import struct

import numpy as np

from .meshopt_decode import decode_view

_COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}
# What this reader understands; anything else a file requires is refused by name.
_UNDERSTOOD = {"KHR_mesh_quantization", "EXT_meshopt_compression"}
_MESHOPT = "EXT_meshopt_compression"


def _normalized(values: np.ndarray) -> np.ndarray:
    """glTF's normalized signed integers as floats: c / max, at least -1."""
    return np.maximum(values.astype(np.float64) / np.iinfo(values.dtype).max, -1.0)


def _view_bytes(document: dict, view_index: int, glb: bytes, bin_at: int, decoded: dict) -> tuple:
    """A bufferView's bytes and where they start: the BIN chunk's, or a meshopt view's decoded once."""
    view = document["bufferViews"][view_index]
    meshopt = view.get("extensions", {}).get(_MESHOPT)
    if meshopt is None:
        return glb, bin_at + view.get("byteOffset", 0)
    if view_index not in decoded:
        if meshopt["buffer"] != 0:
            raise ValueError("the GLB's compressed data is not in its BIN chunk")
        start = bin_at + meshopt.get("byteOffset", 0)
        decoded[view_index] = decode_view(glb[start:start + meshopt["byteLength"]], meshopt["count"],
                                          meshopt["byteStride"], meshopt["mode"], meshopt.get("filter", "NONE"))
    return decoded[view_index], 0


def read_glb(glb: bytes) -> dict:
    """Positions, normals (Blender's Z-up), UVs (or None) and triangle indices of the GLB."""
    magic, _version, length = struct.unpack_from("<4sII", glb, 0)
    if magic != b"glTF" or length != len(glb):
        raise ValueError("not a GLB")
    json_length, _ = struct.unpack_from("<I4s", glb, 12)
    document = json.loads(glb[20:20 + json_length])
    bin_at = 20 + json_length + 8
    primitive = document["meshes"][0]["primitives"][0]
    decoded = {}

    def accessor(index):
        a = document["accessors"][index]
        view = document["bufferViews"][a["bufferView"]]
        data, view_start = _view_bytes(document, a["bufferView"], glb, bin_at, decoded)
        dtype, width = np.dtype(_COMPONENTS[a["componentType"]]), _WIDTH[a["type"]]
        stride = view.get("byteStride", dtype.itemsize * width)
        start = view_start + a.get("byteOffset", 0)
        values = np.ndarray((a["count"], width), dtype, data, start, (stride, dtype.itemsize)).copy()
        return _normalized(values) if a.get("normalized") else values

    unknown = set(document.get("extensionsRequired", [])) - _UNDERSTOOD
    if unknown:
        raise ValueError("the GLB needs " + ", ".join(sorted(unknown)) + "; ask for the float encoding")
    attributes = primitive["attributes"]
    # The node's scale (the quantization grid's step) and translation (the grid's centre, and the
    # mesh's origin when it lies far from the origin: docs/GLB.md, docs/FAR-FROM-ORIGIN.md).
    node = document["nodes"][0]
    y_up = accessor(attributes["POSITION"]).astype(np.float64) * np.array(node.get("scale", [1, 1, 1])) \
        + np.array(node.get("translation", [0, 0, 0]))
    normals = accessor(attributes["NORMAL"]).astype(np.float64)
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    return {
        "positions": np.stack([y_up[:, 0], -y_up[:, 2], y_up[:, 1]], axis=1),  # from_y_up
        "normals": np.stack([normals[:, 0], -normals[:, 2], normals[:, 1]], axis=1),
        "uvs": accessor(attributes["TEXCOORD_0"]) if "TEXCOORD_0" in attributes else None,
        "indices": accessor(primitive["indices"]).reshape(-1).astype(np.int64),
    }


def build_mesh(bpy, name: str, glb: bytes):
    """A new Blender mesh datablock from the GLB."""
    return mesh_from(bpy, name, prepare_mesh(glb))


def prepare_mesh(glb: bytes) -> dict:
    """The GLB read and its vertices welded: NumPy only, no bpy, so live mode does it on its worker
    thread and leaves only mesh_from to Blender's."""
    data = read_glb(glb)
    positions, indices = data["positions"], data["indices"]
    # Weld: the GLB's copies repeat their vertex's position bit for bit.
    keys = np.ascontiguousarray(positions.astype(np.float32)).view(np.dtype((np.void, 12))).reshape(-1)
    _, weld = np.unique(keys, return_inverse=True)
    first = np.full(weld.max() + 1 if len(weld) else 0, len(weld), dtype=np.int64)
    np.minimum.at(first, weld, np.arange(len(weld)))
    data["vertices"] = positions[first]
    data["triangles"] = weld[indices].reshape(-1, 3)
    # normals_split_custom_set takes a sequence of vectors: made here, off Blender's thread in live mode.
    data["corner_normals"] = data["normals"][indices].tolist()
    return data


def mesh_from(bpy, name: str, data: dict):
    """A new Blender mesh datablock from prepare_mesh's arrays, filled through foreach_set (array
    copies; live mode runs this on Blender's thread)."""
    vertices, triangles, corners = data["vertices"], data["triangles"], data["indices"]
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(vertices))
    mesh.vertices.foreach_set("co", vertices.astype(np.float32).reshape(-1))
    mesh.loops.add(triangles.size)
    mesh.loops.foreach_set("vertex_index", triangles.astype(np.int32).reshape(-1))
    mesh.polygons.add(len(triangles))
    mesh.polygons.foreach_set("loop_start", np.arange(0, triangles.size, 3, dtype=np.int32))
    try:
        mesh.polygons.foreach_set("loop_total", np.full(len(triangles), 3, dtype=np.int32))
    except (AttributeError, TypeError, RuntimeError):  # read-only from Blender 3.6: sizes follow from loop_start
        pass
    mesh.update(calc_edges=True)
    # Loop 3 t + k is corner k of triangle t: what the GLB vertex of that corner carried.
    if data["uvs"] is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        layer.data.foreach_set("uv", data["uvs"][corners].astype(np.float32).reshape(-1))
    if hasattr(mesh, "use_auto_smooth"):  # Blender before 4.1: custom normals need it
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = 3.14159
    mesh.polygons.foreach_set("use_smooth", np.ones(len(triangles), dtype=bool))
    mesh.normals_split_custom_set(data["corner_normals"])
    _mark_sharp_edges(mesh, data["normals"], corners)
    mesh.update()
    return mesh


def _mark_sharp_edges(mesh, normals, loop_sources) -> None:
    """An edge is sharp where the faces on it carry different normals at one of its ends: each
    loop's edge runs from its vertex to the next loop's, so each loop gives its edge the normal of
    its corner at its own end, and the next corner's at the other."""
    loops = len(mesh.loops)
    if loops == 0:
        return
    edge, vertex = np.empty(loops, dtype=np.int64), np.empty(loops, dtype=np.int64)
    mesh.loops.foreach_get("edge_index", edge)
    mesh.loops.foreach_get("vertex_index", vertex)
    edge_vertices = np.empty(2 * len(mesh.edges), dtype=np.int64)
    mesh.edges.foreach_get("vertices", edge_vertices)
    first = edge_vertices[0::2]
    next_loop = np.arange(loops) + 1
    next_loop[2::3] -= 3  # triangles: the corner after the third is the first
    keys = np.ascontiguousarray(normals.astype(np.float64)).view(np.dtype((np.void, 24))).reshape(-1)
    _, normal_id = np.unique(keys, return_inverse=True)
    corner_normal = normal_id.reshape(-1)[loop_sources]
    # An edge's end as one number (2 edge + 0 at its first vertex, 1 at its second), and with the
    # normal carried there as another: ends with more than one distinct normal make a sharp edge.
    end = np.concatenate([2 * edge + (vertex != first[edge]), 2 * edge + (vertex[next_loop] != first[edge])])
    carried = end * (int(normal_id.max()) + 1) + np.concatenate([corner_normal, corner_normal[next_loop]])
    distinct_ends = np.unique(carried) // (int(normal_id.max()) + 1)
    normals_at_end = np.bincount(distinct_ends, minlength=2 * len(mesh.edges))
    sharp = (normals_at_end[0::2] > 1) | (normals_at_end[1::2] > 1)
    mesh.edges.foreach_set("use_edge_sharp", sharp)
