"""What a headless Blender test of the add-on needs beside Blender: a real tessera-server on
loopback, the add-on enabled against it, the creased cube the live and bake tests send, what the
add-on's panel shows, the server's /metrics counters, and OBJ files (cage with its crease and corner
tags, result) for tessera-limit-check."""
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path


def start_server(server_binary: str):
    """tessera-server on 127.0.0.1 with a scratch SQLite store: (process, gRPC address, metrics address)."""
    scratch = tempfile.mkdtemp()
    ready = Path(scratch) / "ready"
    process = subprocess.Popen([server_binary, "--listen", "127.0.0.1:0", "--store", f"sqlite:{scratch}/tessera.db",
                                "--metrics-listen", "127.0.0.1:0", "--ready-file", str(ready), "--log-level", "warn"])
    for _ in range(400):
        if ready.exists() and "metrics=" in ready.read_text():
            break
        assert process.poll() is None, f"tessera-server exited with {process.returncode}"
        time.sleep(0.05)
    lines = ready.read_text().splitlines()
    return process, next(line[5:] for line in lines if line.startswith("grpc=")), \
        next(line[8:] for line in lines if line.startswith("metrics="))


def enable_addon(address: str):
    """Blender's factory settings and the add-on enabled as a user enables it, pointed at the
    server at `address`: its preferences."""
    import addon_utils  # noqa: PLC0415 (Blender's modules: these functions run inside Blender)
    import bpy  # noqa: PLC0415
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("tessera_subdiv", default_set=True)
    preferences = bpy.context.preferences.addons["tessera_subdiv"].preferences
    preferences.server = address
    return preferences


class PanelLayout:
    """Records the labels the panel's draw() puts on screen (background mode draws no panels),
    each with whether it was drawn as an alert."""

    def __init__(self):
        self.labels, self.alert = [], False

    def prop(self, *args, **kwargs):
        pass

    def operator(self, *args, **kwargs):
        pass

    def row(self):
        return self

    def column(self):
        return self

    def label(self, text="", icon="NONE"):
        self.labels.append((text, self.alert))


def panel_labels(active=None):
    """The Tessera panel's labels as (text, alert), for the active object (`active` made it first)."""
    import bpy  # noqa: PLC0415
    import tessera_subdiv  # noqa: PLC0415
    if active is not None:
        bpy.context.view_layer.objects.active = active
    layout = PanelLayout()
    tessera_subdiv.TESSERA_PT_panel.draw(type("Panel", (), {"layout": layout})(), bpy.context)
    return layout.labels


def creased_cube(uv_smooth: str = "PRESERVE_BOUNDARIES", corner: bool = True, vertical_crease: float = 0.0):
    """Blender's cube (with its UV unwrap) away from the origin, its top rim infinitely sharp, one
    bottom corner a semi-sharp corner (unless not `corner`), the vertical edge at +x +y creased by
    `vertical_crease` (Blender's crease, 0: none), a Subdivision modifier with the UV rule uv_smooth."""
    import bmesh  # noqa: PLC0415 (Blender's modules: this file is imported outside Blender too)
    import bpy  # noqa: PLC0415
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(1.0, 2.0, 0.5), rotation=(0.0, 0.0, 0.3))
    cube = bpy.context.active_object
    cube.name = "Cage"
    mesh = bmesh.new()
    mesh.from_mesh(cube.data)
    edge_crease, vertex_crease = mesh.edges.layers.crease.verify(), mesh.verts.layers.crease.verify()
    for edge in mesh.edges:
        a, b = (v.co for v in edge.verts)
        if a.z > 0 and b.z > 0:
            edge[edge_crease] = 1.0
        elif vertical_crease and a.x > 0 and b.x > 0 and a.y > 0 and b.y > 0:
            edge[edge_crease] = vertical_crease
    if corner:
        next(v for v in mesh.verts if v.co.z < 0 and v.co.x < 0 and v.co.y < 0)[vertex_crease] = 0.8
    mesh.to_mesh(cube.data)
    mesh.free()
    cube.modifiers.new("Subdivision", "SUBSURF").uv_smooth = uv_smooth
    return cube


def metric(metrics_address: str, name: str) -> float:
    """A counter from the server's /metrics."""
    with urllib.request.urlopen(f"http://{metrics_address}/metrics", timeout=10) as response:
        for line in response.read().decode().splitlines():
            if line.startswith(name + " "):
                return float(line.split()[1])
    raise AssertionError(f"/metrics has no {name}")


def write_obj(path: Path, positions, faces, uvs, corner_uvs, creases=(), corners=()):
    with open(path, "w") as f:
        for i in range(0, len(positions), 3):
            f.write(f"v {positions[i]!r} {positions[i + 1]!r} {positions[i + 2]!r}\n")
        for i in range(0, len(uvs), 2):
            f.write(f"vt {uvs[i]!r} {uvs[i + 1]!r}\n")
        for face, face_uvs in zip(faces, corner_uvs):
            f.write("f " + " ".join(f"{v + 1}/{t + 1}" for v, t in zip(face, face_uvs)) + "\n")
        for v0, v1, sharpness in creases:
            f.write(f"t crease 2/1/0 {v0} {v1} {sharpness!r}\n")
        for vertex, sharpness in corners:
            f.write(f"t corner 1/1/0 {vertex} {sharpness!r}\n")


def write_cage(path: Path, cage) -> None:
    """The add-on's Cage (Y-up, as sent) as an OBJ with its tags."""
    faces, corner_uvs, offset = [], [], 0
    for size in cage.face_sizes:
        faces.append(cage.face_vertices[offset:offset + size])
        corner_uvs.append(cage.uv_indices[offset:offset + size])
        offset += size
    write_obj(path, cage.positions, faces, cage.uvs, corner_uvs, cage.creases, cage.corners)


def write_result(path: Path, mesh, to_y_up) -> None:
    """A Blender triangle mesh (the result) in the cage's Y-up frame, its UVs per corner."""
    positions = [c for v in mesh.vertices for c in to_y_up(*v.co)]
    uvs, faces, corner_uvs = [], [], []
    layer = mesh.uv_layers.active.data
    for polygon in mesh.polygons:
        faces.append(list(polygon.vertices))
        corner_uvs.append([])
        for loop in range(polygon.loop_start, polygon.loop_start + polygon.loop_total):
            corner_uvs[-1].append(len(uvs) // 2)
            uvs.extend(layer[loop].uv)
    write_obj(path, positions, faces, uvs, corner_uvs)
