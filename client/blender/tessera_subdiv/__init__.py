"""Tessera for Blender: tessellates an object's Catmull-Clark limit surface on a tessera-server
within a tolerance, or to pixel accuracy for the scene's camera, and brings the result in as a new
object beside the source; in live mode, again on every edit, frame and viewport move
(client/blender/README.md)."""
bl_info = {
    "name": "Tessera subdivision",
    "author": "Tessera",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Modifiers (an object with a Subdivision Surface modifier)",
    "description": "Adaptive, error-bounded tessellation of the limit surface on a tessera-server",
    "category": "Object",
}

import time

import bpy

from . import bake, live
from .cage import read_cage, subdivision_modifier
from .glb_mesh import build_mesh
from .request import (RESULT_SUFFIX, Accuracy, TesseraError, as_tessera_error, glb_encoding, mesh_id,  # noqa: F401
                      place_result, scene_camera, tessellate_cage, upload_cage)


def tessellate_object(context, obj, server: str, token: str = "", mode: str = "RELATIVE", tolerance: float = 1e-3,
                      pixel_accuracy: float = 0.5, timeout: float = 120.0, encoding: str = "AUTO"):
    """Sends the object's cage and brings back its tessellation as `<name>_tessera` (created, or its
    mesh replaced only once the new one has arrived). Raises TesseraError with the server's or the
    add-on's message."""
    from tessera_client import TesseraClient  # noqa: PLC0415 (the client package is found at call time)
    cage = read_cage(obj)
    if not cage.face_sizes:
        raise TesseraError(f"{obj.name} has no faces")
    encoding = glb_encoding(server, encoding)
    try:
        accuracy = Accuracy(mode, tolerance, pixel_accuracy)
        if mode == "PIXEL":
            accuracy.camera = scene_camera(context.scene, obj)
        identifier = mesh_id(cage)
        with TesseraClient(server, token=token or None) as client:
            upload_cage(client, identifier, cage, obj.name, timeout)
            result = tessellate_cage(client, identifier, accuracy, encoding, timeout)
        mesh = build_mesh(bpy, obj.name + RESULT_SUFFIX, result.glb)
    except Exception as error:
        converted = as_tessera_error(error)
        if converted is error:
            raise
        raise converted from error
    return place_result(context, obj, mesh, result.summary, encoding, len(result.glb)), result.summary


class TesseraPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__
    server: bpy.props.StringProperty(name="Server", default="127.0.0.1:50051")
    token: bpy.props.StringProperty(name="Token", default="", subtype="PASSWORD")
    encoding: bpy.props.EnumProperty(name="GLB encoding", items=[
        ("AUTO", "Auto", "Float from a server on this machine, meshopt from any other"),
        ("MESHOPT", "Meshopt", "Compressed (0.3-0.4 of float on the wire), decoded by the add-on"),
        ("FLOAT", "Float", "Uncompressed float32: nothing to decode"),
    ], default="AUTO")
    live_debounce: bpy.props.FloatProperty(
        name="Live debounce", default=0.1, min=0.0, max=5.0, subtype="TIME", unit="TIME",
        description="Live mode sends a change once the cage has been still this long (seconds)")

    def draw(self, context):
        self.layout.prop(self, "server")
        self.layout.prop(self, "token")
        self.layout.prop(self, "encoding")
        self.layout.prop(self, "live_debounce")


def _live_toggled(settings, context):
    obj = settings.id_data
    if settings.live:
        live.start(obj)
    else:
        live.stop(obj)


def _request_changed(settings, context):
    session = live.session_of(settings.id_data)
    if session is not None:
        session.note_change("settings")


class TesseraSettings(bpy.types.PropertyGroup):
    mode: bpy.props.EnumProperty(name="Accuracy", items=[
        ("RELATIVE", "Relative", "A fraction of the cage's bounding-box diagonal"),
        ("ABSOLUTE", "Absolute", "Object units"),
        ("PIXEL", "Pixels", "Pixel accuracy for the scene camera at the render resolution "
                            "(in live mode, for the active 3D viewport)"),
    ], default="RELATIVE", update=_request_changed)
    tolerance: bpy.props.FloatProperty(name="Tolerance", default=1e-3, min=1e-9, precision=6,
                                       update=_request_changed)
    pixel_accuracy: bpy.props.FloatProperty(name="Pixels", default=0.5, min=1e-3, update=_request_changed)
    live: bpy.props.BoolProperty(
        name="Live", default=False, update=_live_toggled,
        description="Send every change of the cage (and, in pixel mode, of the viewport's view) and update "
                    "<name>_tessera in place; hides the Subdivision modifier in the viewport while on")


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


def subdivided_mesh_active(context) -> bool:
    """The active object is a mesh with a Subdivision modifier: what baking and the panel work on."""
    obj = context.active_object
    return obj is not None and obj.type == "MESH" and subdivision_modifier(obj) is not None


class TESSERA_OT_bake_frames(bpy.types.Operator):
    """Tessellate every frame of a range on the Tessera server, each kept as an object shown on its
    frame (Esc cancels; the frames baked so far stay)"""
    bl_idname = "object.tessera_bake_frames"
    bl_label = "Bake frame range"
    bl_options = {"REGISTER"}

    frame_start: bpy.props.IntProperty(name="Start", default=-1, description="First frame (-1: the scene's start)")
    frame_end: bpy.props.IntProperty(name="End", default=-1, description="Last frame (-1: the scene's end)")

    @classmethod
    def poll(cls, context):
        return subdivided_mesh_active(context)

    def _start(self, context):
        scene = context.scene
        start = scene.frame_start if self.frame_start < 0 else self.frame_start
        end = scene.frame_end if self.frame_end < 0 else self.frame_end
        return bake.start(context, context.active_object, start, end)

    def invoke(self, context, event):
        """A modal bake: a timer steps it (Blender stays responsive; the panel shows progress)."""
        try:
            self._bake = self._start(context)
        except TesseraError as error:
            self.report({"ERROR"}, f"Tessera: {error}")
            return {"CANCELLED"}
        self._timer = context.window_manager.event_timer_add(0.05, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type in ("TIMER", "ESC"):
            self._bake.on_event(context, event.type)
        if self._bake.state == "running":
            return {"RUNNING_MODAL"} if event.type == "ESC" else {"PASS_THROUGH"}
        context.window_manager.event_timer_remove(self._timer)
        self.report({"ERROR" if self._bake.state == "failed" else "INFO"}, f"Tessera: {self._bake.progress()}")
        return {"FINISHED"} if self._bake.state == "finished" else {"CANCELLED"}

    def execute(self, context):
        """From a script: the whole range, blocking."""
        try:
            running = self._start(context)
        except TesseraError as error:
            self.report({"ERROR"}, f"Tessera: {error}")
            return {"CANCELLED"}
        while running.on_event(context, "TIMER"):
            time.sleep(0.01)
        self.report({"ERROR" if running.state == "failed" else "INFO"}, f"Tessera: {running.progress()}")
        return {"FINISHED"} if running.state == "finished" else {"CANCELLED"}


class TESSERA_PT_panel(bpy.types.Panel):
    bl_label = "Tessera"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "modifier"

    @classmethod
    def poll(cls, context):
        return subdivided_mesh_active(context)

    def draw(self, context):
        obj = context.active_object
        settings = obj.tessera
        layout = self.layout
        layout.prop(settings, "mode")
        layout.prop(settings, "pixel_accuracy" if settings.mode == "PIXEL" else "tolerance")
        row = layout.row()
        row.operator(TESSERA_OT_tessellate.bl_idname)
        row.prop(settings, "live", toggle=True)
        layout.operator(TESSERA_OT_bake_frames.bl_idname)
        baking = bake.bake_of(obj)
        if baking is not None:
            column = layout.column()
            column.alert = baking.state == "failed"
            column.label(text=baking.progress(), icon="ERROR" if baking.state == "failed" else "NONE")
        session = live.session_of(obj)
        if session is None:
            return
        if session.summary is not None:
            summary = session.summary
            layout.label(text=f"{summary.triangles:,} triangles, within {summary.guaranteed_bound:.3g}")
            layout.label(text=f"Round trip {1000 * session.round_trip_s:.0f} ms"
                              + (" (sending)" if session.pending() else ""))
        elif session.pending():
            layout.label(text="Sending...")
        if session.error:
            column = layout.column()
            column.alert = True
            column.label(text=session.error, icon="ERROR")


_CLASSES = (TesseraPreferences, TesseraSettings, TESSERA_OT_tessellate, TESSERA_OT_bake_frames, TESSERA_PT_panel)


def register():
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.tessera = bpy.props.PointerProperty(type=TesseraSettings)
    live.register()


def unregister():
    bake.stop_all()
    live.unregister()
    del bpy.types.Object.tessera
    for cls in reversed(_CLASSES):
        bpy.utils.unregister_class(cls)
