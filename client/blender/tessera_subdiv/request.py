"""One request to a tessera-server, shared by the panel's button and live mode: the cage uploaded
(named by its content), its limit surface tessellated within the accuracy asked, and the result
placed as `<name>_tessera`. The network part (upload_cage, tessellate_cage) uses no bpy, so live
mode runs it on its worker thread; place_result runs on Blender's."""
import hashlib
import math
from dataclasses import dataclass
from typing import Optional, Tuple

import bpy
from mathutils import Vector

from .cage import Cage, to_y_up

RESULT_SUFFIX = "_tessera"
_LOOPBACK_HOSTS = ("127.", "localhost", "[::1]", "::1", "ipv4:127.", "ipv6:[::1]")


class TesseraError(Exception):
    """A request that did not come back: the server's message, or the add-on's."""


def glb_encoding(server: str, choice: str = "AUTO") -> str:
    """The GLB encoding to ask for. meshopt files are 0.3-0.4 of the float ones on the wire, and
    decoding them in Python (meshopt_decode.py) costs about 1.3 us a triangle: worth it across a
    network, not on loopback, where AUTO asks for float."""
    if choice != "AUTO":
        return choice.lower()
    host = server.split("///")[-1].lower()
    return "float" if host.startswith(_LOOPBACK_HOSTS) else "meshopt"


def mesh_id(cage: Cage) -> str:
    """Content-addressed: the same cage and rules are uploaded once."""
    digest = hashlib.sha256(repr((cage.positions, cage.face_sizes, cage.face_vertices, cage.creases, cage.corners,
                                  cage.uvs, cage.uv_indices, cage.boundary, cage.uv_interpolation)).encode())
    return "blender-" + digest.hexdigest()[:24]


def camera_in_object_frame(obj, camera_to_world, fov_y_deg: float, width: int, height: int):
    """A camera (its world matrix: looking down its -Z, +Y up) as the client's Camera in the
    object's own frame, Y-up, as the cage is sent."""
    from tessera_client import Camera  # noqa: PLC0415 (the client package is found at call time)
    local = obj.matrix_world.inverted() @ camera_to_world
    eye = local.translation
    rotation = local.to_3x3()
    forward, up = rotation @ Vector((0.0, 0.0, -1.0)), rotation @ Vector((0.0, 1.0, 0.0))
    return Camera(eye=to_y_up(*eye), target=to_y_up(*(eye + forward)), up=to_y_up(*up), fov_y_deg=fov_y_deg,
                  width=max(1, int(width)), height=max(1, int(height)))


def scene_camera(scene, obj):
    """The scene camera in the object's own frame (Y-up), with the render resolution."""
    camera = scene.camera
    if camera is None:
        raise TesseraError("pixel accuracy needs a scene camera")
    render = scene.render
    scale = render.resolution_percentage / 100.0
    return camera_in_object_frame(obj, camera.matrix_world, math.degrees(camera.data.angle_y),
                                  render.resolution_x * scale, render.resolution_y * scale)


@dataclass
class Accuracy:
    """What is asked: mode RELATIVE (of the cage's diagonal), ABSOLUTE (object units) or PIXEL
    (pixel_accuracy pixels for camera)."""
    mode: str = "RELATIVE"
    tolerance: float = 1e-3
    pixel_accuracy: float = 0.5
    camera: Optional[object] = None

    def key(self) -> Tuple:
        """Equal keys ask for the same tessellation of the same cage."""
        if self.mode == "PIXEL":
            c = self.camera
            return (self.mode, self.pixel_accuracy, c.eye, c.target, c.up, c.fov_y_deg, c.width, c.height)
        return (self.mode, self.tolerance)

    def tessellate_arguments(self) -> dict:
        if self.mode == "PIXEL":
            return {"camera": self.camera, "pixel_accuracy": self.pixel_accuracy}
        return {"absolute" if self.mode == "ABSOLUTE" else "relative": self.tolerance}


def upload_cage(client, identifier: str, cage: Cage, display_name: str, timeout: float,
                same_topology_as: Optional[str] = None, uvs_changed: bool = True,
                origin: Tuple[float, float, float] = (0.0, 0.0, 0.0)) -> str:
    """Uploads the cage as `identifier` unless the server has it. `same_topology_as` names the
    mesh this session uploaded last when the add-on found the topology unchanged since
    (cage.topology_signature), and `uvs_changed` says whether the UV values differ from that
    mesh's: then only the positions (and the UVs if they changed) are sent, on that mesh's
    topology (TesseraClient.upload_positions; issue 48, item 2), and the server keeps the
    topology ready for the tessellation. Should the server not have that mesh any more
    (NOT_FOUND) or refuse the counts (INVALID_ARGUMENT), the whole cage is sent instead.
    `origin` goes to either upload (a positions-only upload does not inherit it); the add-on
    sends object-local positions, so none. Returns what was sent: "positions", "full", or
    "none" for a cage the server already had."""
    from tessera_client import TesseraError as ClientError  # noqa: PLC0415
    import grpc  # noqa: PLC0415
    if same_topology_as is not None:
        try:
            client.upload_positions(identifier, topology_of=same_topology_as, positions=cage.positions,
                                    uvs=cage.uvs if uvs_changed else None, origin=origin,
                                    display_name=display_name, timeout=timeout)
            return "positions"
        except ClientError as error:
            if error.code == grpc.StatusCode.ALREADY_EXISTS:  # the same cage, uploaded before
                return "none"
            if error.code not in (grpc.StatusCode.NOT_FOUND, grpc.StatusCode.INVALID_ARGUMENT):
                raise
            # The mesh it names is gone (deleted, another server) or its counts differ: whole.
    try:
        client.upload_arrays(identifier, cage.positions, cage.face_sizes, cage.face_vertices, creases=cage.creases,
                             corners=cage.corners, display_name=display_name, boundary=cage.boundary,
                             uvs=cage.uvs, uv_indices=cage.uv_indices, uv_interpolation=cage.uv_interpolation,
                             origin=origin, timeout=timeout)
    except ClientError as error:
        if error.code != grpc.StatusCode.ALREADY_EXISTS:  # the same cage, uploaded before
            raise
        return "none"
    return "full"


def tessellate_cage(client, identifier: str, accuracy: Accuracy, encoding: str, timeout: float):
    """The uploaded cage's tessellation (tessera_client.Tessellation)."""
    return client.tessellate(identifier, encoding=encoding, timeout=timeout, **accuracy.tessellate_arguments())


def as_tessera_error(error: Exception) -> Exception:
    """The client's, gRPC's and the GLB reader's errors as TesseraError; others as they are."""
    import grpc  # noqa: PLC0415 (found at call time, as the client package)
    import tessera_client  # noqa: PLC0415
    if isinstance(error, TesseraError):
        return error
    if isinstance(error, tessera_client.TesseraError):
        return TesseraError(error.message)
    if isinstance(error, grpc.RpcError):
        return TesseraError(f"{error.code().name}: {error.details()}")
    if isinstance(error, ValueError):  # a GLB the add-on cannot read
        return TesseraError(f"the GLB could not be read: {error}")
    return error


def place_result(context, obj, mesh, summary, encoding: str, glb_bytes: int):
    """`<name>_tessera` created beside obj, or the same object given the new mesh: its modifiers
    (on the object) kept, its material slots copied onto the new mesh, the old mesh freed and its
    name taken over."""
    name = obj.name + RESULT_SUFFIX
    target = bpy.data.objects.get(name)
    if target is None:
        target = bpy.data.objects.new(name, mesh)
        (obj.users_collection[0] if obj.users_collection else context.scene.collection).objects.link(target)
    else:
        old = target.data
        for material in old.materials:
            mesh.materials.append(material)
        target.data = mesh
        if old.users == 0:
            old_name = old.name
            bpy.data.meshes.remove(old)
            mesh.name = old_name
    target.matrix_world = obj.matrix_world.copy()
    target["tessera_bound"] = summary.guaranteed_bound
    target["tessera_triangles"] = summary.triangles
    target["tessera_encoding"] = encoding
    target["tessera_glb_bytes"] = glb_bytes
    return target
