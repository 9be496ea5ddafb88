"""The control cage of a Blender object as Tessera's arrays: positions turned from Blender's Z-up
into glTF's Y-up, faces, creases and corners from Blender's crease values, UVs from the active
layer, and the Subdivision modifier's boundary and UV rules."""
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

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


def _edge_creases(mesh) -> List[float]:
    attribute = mesh.attributes.get("crease_edge") if hasattr(mesh, "attributes") else None
    if attribute is not None:  # Blender 4.0 and newer
        return [d.value for d in attribute.data]
    return [getattr(e, "crease", 0.0) for e in mesh.edges]  # Blender 3.x


def _vertex_creases(mesh) -> List[float]:
    attribute = mesh.attributes.get("crease_vert") if hasattr(mesh, "attributes") else None
    if attribute is not None:
        return [d.value for d in attribute.data]
    layer = getattr(mesh, "vertex_creases", None)  # Blender 3.x: a layer collection
    if layer is not None and len(layer) > 0:
        return [d.value for d in layer[0].data]
    return [0.0] * len(mesh.vertices)


def read_cage(obj) -> Cage:
    """The object's own mesh (its modifiers not applied) with the first Subdivision modifier's
    rules; creases only when that modifier uses them."""
    mesh = obj.data
    cage = Cage()
    for v in mesh.vertices:
        cage.positions.extend(to_y_up(*v.co))
    for polygon in mesh.polygons:
        cage.face_sizes.append(len(polygon.vertices))
        cage.face_vertices.extend(polygon.vertices)
    modifier = subdivision_modifier(obj)
    if modifier is None or modifier.use_creases:
        for edge, crease in zip(mesh.edges, _edge_creases(mesh)):
            if crease > 0:
                cage.creases.append((edge.vertices[0], edge.vertices[1], crease_sharpness(crease)))
        for vertex, crease in enumerate(_vertex_creases(mesh)):
            if crease > 0:
                cage.corners.append((vertex, crease_sharpness(crease)))
    if modifier is not None:
        cage.boundary = BOUNDARY.get(modifier.boundary_smooth, "edge_only")
        cage.uv_interpolation = UV_RULE.get(modifier.uv_smooth, "all")
    layer = mesh.uv_layers.active
    if layer is not None:
        # One UV per control vertex and distinct (u, v): the corners of a vertex that share it are
        # continuous there (OpenSubdiv's face-varying values belong to one vertex each).
        index = {}
        for polygon in mesh.polygons:
            for loop in range(polygon.loop_start, polygon.loop_start + polygon.loop_total):
                key = (mesh.loops[loop].vertex_index, tuple(layer.data[loop].uv))
                if key not in index:
                    index[key] = len(index)
                    cage.uvs.extend(key[1])
                cage.uv_indices.append(index[key])
    return cage
