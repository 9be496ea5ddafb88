"""Tessera for Blender: tessellates an object's Catmull-Clark limit surface on a tessera-server
within a tolerance, or to pixel accuracy for the scene's camera, and brings the result in as a new
object beside the source (client/blender/README.md)."""
bl_info = {
    "name": "Tessera subdivision",
    "author": "Tessera",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Modifiers (an object with a Subdivision Surface modifier)",
    "description": "Adaptive, error-bounded tessellation of the limit surface on a tessera-server",
    "category": "Object",
}

import hashlib
import math

import bpy
from mathutils import Vector

from .cage import Cage, read_cage, subdivision_modifier, to_y_up
from .glb_mesh import build_mesh

RESULT_SUFFIX = "_tessera"
_LOOPBACK_HOSTS = ("127.", "localhost", "[::1]", "::1", "ipv4:127.", "ipv6:[::1]")


def glb_encoding(server: str, choice: str = "AUTO") -> str:
    """The GLB encoding to ask for. meshopt files are 0.3-0.4 of the float ones on the wire, and
    decoding them in Python (meshopt_decode.py) costs about 1.3 us a triangle: worth it across a
    network, not on loopback, where AUTO asks for float."""
    if choice != "AUTO":
        return choice.lower()
    host = server.split("///")[-1].lower()
    return "float" if host.startswith(_LOOPBACK_HOSTS) else "meshopt"


class TesseraError(Exception):
    """A request that did not come back: the server's message, or the add-on's."""


def mesh_id(cage: Cage) -> str:
    """Content-addressed: the same cage and rules are uploaded once."""
    digest = hashlib.sha256(repr((cage.positions, cage.face_sizes, cage.face_vertices, cage.creases, cage.corners,
                                  cage.uvs, cage.uv_indices, cage.boundary, cage.uv_interpolation)).encode())
    return "blender-" + digest.hexdigest()[:24]


def scene_camera(scene, obj):
    """The scene camera in the object's own frame (Y-up), with the render resolution."""
    from tessera_client import Camera  # noqa: PLC0415 (the client package is found at call time)
    camera = scene.camera
    if camera is None:
        raise TesseraError("pixel accuracy needs a scene camera")
    local = obj.matrix_world.inverted() @ camera.matrix_world
    eye = local.translation
    rotation = local.to_3x3()
    forward, up = rotation @ Vector((0.0, 0.0, -1.0)), rotation @ Vector((0.0, 1.0, 0.0))
    render = scene.render
    scale = render.resolution_percentage / 100.0
    return Camera(eye=to_y_up(*eye), target=to_y_up(*(eye + forward)), up=to_y_up(*up),
                  fov_y_deg=math.degrees(camera.data.angle_y),
                  width=max(1, int(render.resolution_x * scale)), height=max(1, int(render.resolution_y * scale)))


def tessellate_object(context, obj, server: str, token: str = "", mode: str = "RELATIVE", tolerance: float = 1e-3,
                      pixel_accuracy: float = 0.5, timeout: float = 120.0, encoding: str = "AUTO"):
    """Sends the object's cage and brings back its tessellation as `<name>_tessera` (created, or its
    mesh replaced only once the new one has arrived). Raises TesseraError with the server's or the
    add-on's message."""
    import grpc  # noqa: PLC0415 (found at call time, as the client package)
    import tessera_client  # noqa: PLC0415
    cage = read_cage(obj)
    if not cage.face_sizes:
        raise TesseraError(f"{obj.name} has no faces")
    try:
        return _tessellate(context, obj, cage, server, token, mode, tolerance, pixel_accuracy, timeout,
                           glb_encoding(server, encoding))
    except tessera_client.TesseraError as error:
        raise TesseraError(error.message) from error
    except grpc.RpcError as error:
        raise TesseraError(f"{error.code().name}: {error.details()}") from error
    except ValueError as error:  # a GLB the add-on cannot read
        raise TesseraError(f"the GLB could not be read: {error}") from error


def _tessellate(context, obj, cage, server, token, mode, tolerance, pixel_accuracy, timeout, encoding):
    from tessera_client import TesseraClient, TesseraError as ClientError  # noqa: PLC0415
    import grpc  # noqa: PLC0415
    identifier = mesh_id(cage)
    with TesseraClient(server, token=token or None) as client:
        try:
            client.upload_arrays(identifier, cage.positions, cage.face_sizes, cage.face_vertices, creases=cage.creases,
                                 corners=cage.corners, display_name=obj.name, boundary=cage.boundary,
                                 uvs=cage.uvs, uv_indices=cage.uv_indices, uv_interpolation=cage.uv_interpolation,
                                 timeout=timeout)
        except ClientError as error:
            if error.code != grpc.StatusCode.ALREADY_EXISTS:  # the same cage, uploaded before
                raise
        if mode == "PIXEL":
            result = client.tessellate(identifier, camera=scene_camera(context.scene, obj),
                                       pixel_accuracy=pixel_accuracy, encoding=encoding, timeout=timeout)
        elif mode == "ABSOLUTE":
            result = client.tessellate(identifier, absolute=tolerance, encoding=encoding, timeout=timeout)
        else:
            result = client.tessellate(identifier, relative=tolerance, encoding=encoding, timeout=timeout)
    mesh = build_mesh(bpy, obj.name + RESULT_SUFFIX, result.glb)
    target = bpy.data.objects.get(obj.name + RESULT_SUFFIX)
    if target is None:
        target = bpy.data.objects.new(obj.name + RESULT_SUFFIX, mesh)
        (obj.users_collection[0] if obj.users_collection else context.scene.collection).objects.link(target)
    else:
        old = target.data
        target.data = mesh
        if old.users == 0:
            bpy.data.meshes.remove(old)
    target.matrix_world = obj.matrix_world.copy()
    target["tessera_bound"] = result.summary.guaranteed_bound
    target["tessera_triangles"] = result.summary.triangles
    target["tessera_encoding"] = encoding
    target["tessera_glb_bytes"] = len(result.glb)
    return target, result.summary


class TesseraPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__
    server: bpy.props.StringProperty(name="Server", default="127.0.0.1:50051")
    token: bpy.props.StringProperty(name="Token", default="", subtype="PASSWORD")
    encoding: bpy.props.EnumProperty(name="GLB encoding", items=[
        ("AUTO", "Auto", "Float from a server on this machine, meshopt from any other"),
        ("MESHOPT", "Meshopt", "Compressed (0.3-0.4 of float on the wire), decoded by the add-on"),
        ("FLOAT", "Float", "Uncompressed float32: nothing to decode"),
    ], default="AUTO")

    def draw(self, context):
        self.layout.prop(self, "server")
        self.layout.prop(self, "token")
        self.layout.prop(self, "encoding")


class TesseraSettings(bpy.types.PropertyGroup):
    mode: bpy.props.EnumProperty(name="Accuracy", items=[
        ("RELATIVE", "Relative", "A fraction of the cage's bounding-box diagonal"),
        ("ABSOLUTE", "Absolute", "Object units"),
        ("PIXEL", "Pixels", "Pixel accuracy for the scene camera at the render resolution"),
    ], default="RELATIVE")
    tolerance: bpy.props.FloatProperty(name="Tolerance", default=1e-3, min=1e-9, precision=6)
    pixel_accuracy: bpy.props.FloatProperty(name="Pixels", default=0.5, min=1e-3)


class TESSERA_OT_tessellate(bpy.types.Operator):
    """Tessellate the limit surface on the Tessera server"""
    bl_idname = "object.tessera_tessellate"
    bl_label = "Tessellate on Tessera"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def execute(self, context):
        obj = context.active_object
        settings = obj.tessera
        preferences = context.preferences.addons[__name__].preferences
        try:
            target, summary = tessellate_object(context, obj, preferences.server, preferences.token, settings.mode,
                                                settings.tolerance, settings.pixel_accuracy,
                                                encoding=preferences.encoding)
        except Exception as error:  # the server's message (or ours) goes to the UI; the old result stays
            self.report({"ERROR"}, f"Tessera: {error}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Tessera: {summary.triangles} triangles within {summary.guaranteed_bound:.3g}")
        return {"FINISHED"}


class TESSERA_PT_panel(bpy.types.Panel):
    bl_label = "Tessera"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "modifier"

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and subdivision_modifier(obj) is not None

    def draw(self, context):
        settings = context.active_object.tessera
        self.layout.prop(settings, "mode")
        self.layout.prop(settings, "pixel_accuracy" if settings.mode == "PIXEL" else "tolerance")
        self.layout.operator(TESSERA_OT_tessellate.bl_idname)


_CLASSES = (TesseraPreferences, TesseraSettings, TESSERA_OT_tessellate, TESSERA_PT_panel)


def register():
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.tessera = bpy.props.PointerProperty(type=TesseraSettings)


def unregister():
    del bpy.types.Object.tessera
    for cls in reversed(_CLASSES):
        bpy.utils.unregister_class(cls)
