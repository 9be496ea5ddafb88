"""The control cage of a Blender object as Tessera's arrays: positions turned from Blender's Z-up
into glTF's Y-up, faces, creases and corners from Blender's crease values, UVs from the active
layer, and the Subdivision modifier's boundary and UV rules. Live mode reads the evaluated cage
(what the Subdivision modifier would be given: shape keys, armatures, the edit mesh) and compares
topology signatures to tell a position-only edit from a change of topology."""
import hashlib
from dataclasses import dataclass, field
from typing import List, Tuple

import numpy as np

# Blender's OpenSubdiv bridge maps a crease value c in [0, 1] to sharpness 10 c² (and 1 to
# infinitely sharp, OpenSubdiv's 10).
def crease_sharpness(crease: float) -> float:
    return 10.0 * crease * crease


# The Subdivision modifier's rules as OpenSubdiv's (and the Python client's) names.
BOUNDARY = {"ALL": "edge_only", "PRESERVE_CORNERS": "edge_and_corner"}
UV_RULE = {
    "NONE": "all",
    "PRESERVE_CORNERS": "corners_only",
    "PRESERVE_CORNERS_AND_JUNCTIONS": "corners_plus1",
    "PRESERVE_CORNERS_JUNCTIONS_AND_CONCAVE": "corners_plus2",
    "PRESERVE_BOUNDARIES": "boundaries",
    "SMOOTH_ALL": "none",
}


def to_y_up(x: float, y: float, z: float) -> Tuple[float, float, float]:
    return x, z, -y


def from_y_up(x: float, y: float, z: float) -> Tuple[float, float, float]:
    return x, -z, y


@dataclass
class Cage:
    positions: List[float] = field(default_factory=list)
    face_sizes: List[int] = field(default_factory=list)
    face_vertices: List[int] = field(default_factory=list)
    creases: List[Tuple[int, int, float]] = field(default_factory=list)
    corners: List[Tuple[int, float]] = field(default_factory=list)
    uvs: List[float] = field(default_factory=list)
    uv_indices: List[int] = field(default_factory=list)
    boundary: str = "edge_only"
    uv_interpolation: str = "all"


def subdivision_modifier(obj):
    """The object's first Subdivision Surface modifier, or None."""
    return next((m for m in obj.modifiers if m.type == "SUBSURF"), None)


def _values(collection, attribute: str, width: int = 1, dtype=np.float32) -> np.ndarray:
    """One attribute of every element, copied in one call (foreach_get)."""
    values = np.empty(len(collection) * width, dtype=dtype)
    collection.foreach_get(attribute, values)
    return values


def _edge_creases(mesh) -> np.ndarray:
    attribute = mesh.attributes.get("crease_edge") if hasattr(mesh, "attributes") else None
    if attribute is not None:  # Blender 4.0 and newer
        return _values(attribute.data, "value")
    return _values(mesh.edges, "crease")  # Blender 3.x


def _vertex_creases(mesh) -> np.ndarray:
    attribute = mesh.attributes.get("crease_vert") if hasattr(mesh, "attributes") else None
    if attribute is not None:
        return _values(attribute.data, "value")
    layer = getattr(mesh, "vertex_creases", None)  # Blender 3.x: a layer collection
    if layer is not None and len(layer) > 0:
        return _values(layer[0].data, "value")
    return np.zeros(len(mesh.vertices), dtype=np.float32)


def _sharpness(creases: np.ndarray) -> np.ndarray:
    """crease_sharpness of each, in the same order of operations (the same doubles)."""
    creases = creases.astype(np.float64)
    return 10.0 * creases * creases


def read_cage(obj, mesh=None) -> Cage:
    """The object's own mesh (its modifiers not applied), or `mesh` (the evaluated cage), with the
    first Subdivision modifier's rules; creases only when that modifier uses them. Read with
    foreach_get (live mode reads it on Blender's thread at every send)."""
    mesh = obj.data if mesh is None else mesh
    cage = Cage()
    co = _values(mesh.vertices, "co", 3).astype(np.float64).reshape(-1, 3)
    cage.positions = np.stack([co[:, 0], co[:, 2], -co[:, 1]], axis=1).reshape(-1).tolist()  # to_y_up
    sizes = _values(mesh.polygons, "loop_total", dtype=np.int64)
    starts = _values(mesh.polygons, "loop_start", dtype=np.int64)
    # Each face corner's loop, faces in order (a face's loops are consecutive from its loop_start).
    corner_loops = np.repeat(starts - (np.cumsum(sizes) - sizes), sizes) + np.arange(int(sizes.sum()))
    face_vertices = _values(mesh.loops, "vertex_index", dtype=np.int64)[corner_loops]
    cage.face_sizes, cage.face_vertices = sizes.tolist(), face_vertices.tolist()
    modifier = subdivision_modifier(obj)
    if modifier is None or modifier.use_creases:
        edge_creases = _edge_creases(mesh)
        creased = np.flatnonzero(edge_creases > 0)
        ends = _values(mesh.edges, "vertices", 2, np.int64).reshape(-1, 2)[creased]
        cage.creases = list(zip(ends[:, 0].tolist(), ends[:, 1].tolist(), _sharpness(edge_creases[creased]).tolist()))
        vertex_creases = _vertex_creases(mesh)
        cornered = np.flatnonzero(vertex_creases > 0)
        cage.corners = list(zip(cornered.tolist(), _sharpness(vertex_creases[cornered]).tolist()))
    if modifier is not None:
        cage.boundary = BOUNDARY.get(modifier.boundary_smooth, "edge_only")
        cage.uv_interpolation = UV_RULE.get(modifier.uv_smooth, "all")
    layer = mesh.uv_layers.active
    if layer is not None:
        # One UV per control vertex and distinct (u, v), numbered as first met: the corners of a
        # vertex that share it are continuous there (OpenSubdiv's face-varying values belong to
        # one vertex each). + 0.0 makes -0.0 the same UV as 0.0, as Python's == does.
        corner_uvs = _values(layer.data, "uv", 2).reshape(-1, 2)[corner_loops] + np.float32(0.0)
        keys = np.empty((len(corner_loops), 3), dtype=np.uint32)
        keys[:, 0] = face_vertices
        keys[:, 1:] = corner_uvs.view(np.uint32)
        _, first, inverse = np.unique(keys.view(np.dtype((np.void, 12))).reshape(-1), return_index=True,
                                      return_inverse=True)
        order = np.argsort(first)
        rank = np.empty_like(order)
        rank[order] = np.arange(len(order))
        cage.uv_indices = rank[inverse.reshape(-1)].tolist()
        cage.uvs = corner_uvs[first[order]].astype(np.float64).reshape(-1).tolist()
    return cage


def topology_signature(cage: Cage) -> str:
    """What the server's topology cache is keyed by (docs/DECISIONS.md, "Edits reuse topology"):
    faces, creases, corners, rules, UV indices and the vertex and UV-value counts; not the
    positions or the UV values. Equal signatures: an edit that only moved vertices (or UVs)."""
    return hashlib.sha256(repr((len(cage.positions), cage.face_sizes, cage.face_vertices, cage.creases,
                                cage.corners, len(cage.uvs), cage.uv_indices, cage.boundary,
                                cage.uv_interpolation)).encode()).hexdigest()


class CageError(Exception):
    """The evaluated cage cannot be read as the Subdivision modifier's input."""


def evaluated_cage(obj, depsgraph) -> Cage:
    """The cage as the object's first Subdivision modifier receives it: the edit mesh in edit mode,
    shape keys, armatures and the modifiers above it applied. Live mode hides that modifier in the
    viewport (its result is `<name>_tessera`), so the evaluated object is its input, provided no
    modifier below it is shown in the viewport."""
    modifier = subdivision_modifier(obj)
    if modifier is None:
        raise CageError(f"{obj.name} has no Subdivision Surface modifier")
    if modifier.show_viewport:
        raise CageError(f"{obj.name}'s Subdivision modifier is shown in the viewport (live mode hides it)")
    below = obj.modifiers[list(obj.modifiers).index(modifier) + 1:]
    shown = [m.name for m in below if m.show_viewport]
    if shown:
        raise CageError("live mode needs the Subdivision modifier last among the modifiers shown in the viewport; "
                        "below it: " + ", ".join(shown))
    others = [m for m in obj.modifiers if m != modifier and m.show_viewport]
    if obj.mode == "SCULPT" and not others and obj.data.shape_keys is None:
        # A brush stroke writes into the mesh itself and may tag only a redraw until it ends:
        # with nothing between mesh and cage, the mesh is the cage.
        return read_cage(obj)
    evaluated = obj.evaluated_get(depsgraph)
    # Without arguments: to_mesh(preserve_all_data_layers=True, depsgraph=...) evaluates the
    # original mesh again, which in edit mode is not the edit mesh (Blender 3.4).
    mesh = evaluated.to_mesh()
    try:
        return read_cage(obj, mesh)
    finally:
        evaluated.to_mesh_clear()
