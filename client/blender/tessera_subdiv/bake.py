"""Bake frame range: each frame's evaluated cage (shape keys, armatures, modifiers above the
Subdivision one) sent to the server and its tessellation kept as a mesh of its own, one object a
frame, shown only on its frame (client/blender/README.md says why meshes and not shape keys).

A Bake is stepped by the operator's timer (on_event "TIMER", on Blender's thread): it sets the
next frame, reads the cage and hands it to a worker thread (live mode's Worker: the upload, the
tessellation and the GLB's reading happen off Blender's thread), and makes the object of each
frame that comes back. A frame whose topology is the one before's is uploaded positions-only.
Esc (on_event "ESC") cancels: the request in flight is dropped, the frames baked so far stay.
Either way the scene's frame and the Subdivision modifier's viewport visibility are put back."""
import time
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import bpy

from .cage import Cage, CageError, evaluated_cage, subdivision_modifier, topology_signature
from .glb_mesh import mesh_from
from .live import Job, Worker
from .request import Accuracy, TesseraError, glb_encoding, mesh_id, scene_camera

BAKE_SUFFIX = "_tessera_bake"


def frame_object_name(name: str, frame: int) -> str:
    return f"{name}_tessera_f{frame:04d}"


@dataclass
class Bake:
    """One object's bake in progress (or its outcome): state "running", "finished", "cancelled"
    or "failed" (error says why)."""
    name: str
    frames: List[int]
    original_frame: int
    hid_modifier: Optional[str]
    worker: Worker = field(default_factory=Worker)
    next_index: int = 0
    in_flight: Optional[int] = None     # the frame whose request is out
    state: str = "running"
    error: Optional[str] = None
    baked: List[int] = field(default_factory=list)
    cages: Dict[int, Cage] = field(default_factory=dict)    # what was sent for each frame baked
    matrices: Dict[int, object] = field(default_factory=dict)  # the object's world matrix at each frame sent
    records: Dict[int, dict] = field(default_factory=dict)  # each frame's upload, triangles, bound, times
    sent_identifier: Optional[str] = None
    sent_signature: Optional[str] = None
    sent_uvs: Optional[list] = None
    started_at: float = field(default_factory=time.perf_counter)
    ended_at: float = 0.0

    def progress(self) -> str:
        """What the panel says of it."""
        done, total = len(self.baked), len(self.frames)
        if self.state == "running":
            frame = self.in_flight if self.in_flight is not None else self.frames[min(self.next_index, total - 1)]
            return f"Baking frame {frame} ({done} of {total} done), Esc cancels"
        if self.state == "finished":
            return f"Baked {done} frames ({self.frames[0]}-{self.frames[-1]}) in {self.ended_at - self.started_at:.1f} s"
        if self.state == "cancelled":
            return f"Bake cancelled: {done} of {total} frames baked"
        return f"Bake failed after {done} of {total} frames: {self.error}"

    def on_event(self, context, event_type: str) -> bool:
        """The operator's events: TIMER steps the bake, ESC cancels it. Returns whether it runs on."""
        if self.state != "running":
            return False
        if event_type == "ESC":
            self._end(context, "cancelled")
        elif event_type == "TIMER":
            try:
                self._step(context)
            except Exception as error:  # noqa: BLE001 (shown, and the bake ends with the frames it has)
                self.error = f"{type(error).__name__}: {error}"
                self._end(context, "failed")
        return self.state == "running"

    def _step(self, context) -> None:
        obj = bpy.data.objects.get(self.name)
        if obj is None:
            raise TesseraError(f"{self.name} is gone")
        for outcome in self.worker.take_outcomes():
            frame = self.in_flight
            self.in_flight = None
            if outcome.error is not None:
                self.error = outcome.error
                self._end(context, "failed")
                return
            self._keep(context, obj, frame, outcome)
        if self.in_flight is None:
            if self.next_index == len(self.frames):
                self._end(context, "finished")
                return
            self._send(context, obj, self.frames[self.next_index])
            self.next_index += 1
        _progress(context, self)

    def _send(self, context, obj, frame: int) -> None:
        scene = context.scene
        scene.frame_set(frame)
        captured_at = time.perf_counter()
        depsgraph = context.evaluated_depsgraph_get()
        settings = obj.tessera
        preferences = context.preferences.addons[__package__].preferences
        cage = evaluated_cage(obj, depsgraph)
        if not cage.face_sizes:
            raise TesseraError(f"{obj.name} has no faces at frame {frame}")
        accuracy = Accuracy(settings.mode, settings.tolerance, settings.pixel_accuracy)
        if settings.mode == "PIXEL":
            accuracy.camera = scene_camera(scene, obj)  # the render camera, at this frame
        identifier = mesh_id(cage)
        signature = topology_signature(cage)
        same_topology_as = self.sent_identifier if signature == self.sent_signature else None
        uvs_changed = cage.uvs != self.sent_uvs
        self.sent_identifier, self.sent_signature, self.sent_uvs = identifier, signature, cage.uvs
        self.cages[frame] = cage
        self.matrices[frame] = obj.matrix_world.copy()
        self.in_flight = frame
        self.worker.submit(Job(frame, identifier, cage, same_topology_as, uvs_changed, accuracy, preferences.server,
                               preferences.token, glb_encoding(preferences.server, preferences.encoding), obj.name,
                               ["bake"], captured_at, captured_at, time.perf_counter() - captured_at))

    def _keep(self, context, obj, frame: int, outcome) -> None:
        """The frame's mesh as an object of the bake's collection: placed where the source was at
        that frame (its transform, animated or not), shown in the viewport and in renders on its
        frame only."""
        name = frame_object_name(self.name, frame)
        mesh = mesh_from(bpy, name, outcome.prepared)
        for material in obj.data.materials:
            mesh.materials.append(material)
        target = bpy.data.objects.new(name, mesh)
        _collection(context, obj).objects.link(target)
        target.matrix_world = self.matrices[frame]
        for attribute in ("hide_viewport", "hide_render"):
            for at, hidden in ((frame - 1, True), (frame, False), (frame + 1, True)):
                setattr(target, attribute, hidden)
                target.keyframe_insert(attribute, frame=at)
        for curve in target.animation_data.action.fcurves:
            for point in curve.keyframe_points:
                point.interpolation = "CONSTANT"
        summary = outcome.summary
        target["tessera_bound"], target["tessera_triangles"] = summary.guaranteed_bound, summary.triangles
        target["tessera_frame"] = frame
        self.baked.append(frame)
        self.records[frame] = {"frame": frame, "upload": outcome.upload, "triangles": summary.triangles,
                               "bound": summary.guaranteed_bound, "upload_s": outcome.upload_s,
                               "tessellate_s": outcome.tessellate_s, "decode_s": outcome.decode_s}

    def _end(self, context, state: str) -> None:
        self.state, self.ended_at = state, time.perf_counter()
        self.worker.stop()  # a request in flight is dropped when it comes back
        self.in_flight = None
        obj = bpy.data.objects.get(self.name)
        if obj is not None and self.hid_modifier is not None:
            modifier = obj.modifiers.get(self.hid_modifier)
            if modifier is not None:
                modifier.show_viewport = True
        context.scene.frame_set(self.original_frame)
        _progress(context, self)


_bakes: Dict[str, Bake] = {}


def bake_of(obj) -> Optional[Bake]:
    """The object's bake under way, or the last one's outcome."""
    return _bakes.get(obj.name)


def _collection(context, obj):
    name = obj.name + BAKE_SUFFIX
    collection = bpy.data.collections.get(name)
    if collection is None:
        collection = bpy.data.collections.new(name)
        (obj.users_collection[0] if obj.users_collection else context.scene.collection).children.link(collection)
    return collection


def _progress(context, bake: Bake) -> None:
    """Blender's progress cursor and the panel (redrawn)."""
    window_manager = context.window_manager
    if bake.state == "running":
        if bake.next_index == 1 and not bake.baked:
            window_manager.progress_begin(0, len(bake.frames))
        window_manager.progress_update(len(bake.baked))
    else:
        window_manager.progress_end()
    for window in window_manager.windows:
        for area in window.screen.areas if window.screen else ():
            if area.type in ("PROPERTIES", "VIEW_3D"):
                area.tag_redraw()


def start(context, obj, frame_start: int, frame_end: int) -> Bake:
    """A bake of frames frame_start..frame_end of obj, replacing the object's last bake (its
    collection emptied). Raises TesseraError for what cannot be baked."""
    if subdivision_modifier(obj) is None:
        raise TesseraError(f"{obj.name} has no Subdivision Surface modifier")
    if obj.tessera.live:
        raise TesseraError("turn Live off to bake: both would send every frame")
    if frame_end < frame_start:
        raise TesseraError(f"the frame range {frame_start}-{frame_end} is empty")
    running = _bakes.get(obj.name)
    if running is not None and running.state == "running":
        raise TesseraError(f"{obj.name} is being baked")
    collection = bpy.data.collections.get(obj.name + BAKE_SUFFIX)
    if collection is not None:
        for old in list(collection.objects):
            mesh = old.data
            bpy.data.objects.remove(old)
            if mesh is not None and mesh.users == 0:
                bpy.data.meshes.remove(mesh)
    modifier = subdivision_modifier(obj)
    hid = None
    if modifier.show_viewport:  # the evaluated object is then the modifier's input, the cage
        modifier.show_viewport = False
        hid = modifier.name
    bake = _bakes[obj.name] = Bake(obj.name, list(range(frame_start, frame_end + 1)), context.scene.frame_current, hid)
    try:
        evaluated_cage(obj, context.evaluated_depsgraph_get())  # refused now rather than at the first timer
    except CageError as error:
        bake.error = str(error)
        bake._end(context, "failed")  # noqa: SLF001
        raise TesseraError(str(error)) from error
    return bake


def stop_all() -> None:
    for bake in _bakes.values():
        bake.worker.stop()
    _bakes.clear()
