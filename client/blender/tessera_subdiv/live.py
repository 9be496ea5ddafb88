"""Live mode: while an object's Live toggle is on, changes of its cage (edit-mode moves, sculpting,
creases, UVs; shape keys and armatures on a frame change) and, in pixel mode, moves of the active
3D viewport's view are sent to the server, and `<name>_tessera` is updated in place.

Threads: Blender's data is read and written only on its own thread, by tick() (a bpy.app.timers
timer) and by the depsgraph and frame-change handlers, which only note that something changed.
A worker thread per live object does the network I/O and reads the GLB (NumPy), so the UI never
waits on the server. Sends are debounced (the preference "Live debounce": a send waits until the
cage has been still that long) and the latest wins: the cage is read when the worker is free, so
an edit made during a request is sent, with whatever followed it, once that request is back.
"""
import threading
import time
import traceback
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import bpy
from bpy.app.handlers import persistent

from .cage import Cage, CageError, evaluated_cage, subdivision_modifier, topology_signature
from .glb_mesh import mesh_from, prepare_mesh
from .request import (Accuracy, TesseraError, as_tessera_error, glb_encoding, mesh_id, place_result, scene_camera,
                      tessellate_cage, upload_cage)
from .viewport import active_viewport_view, viewport_camera

TICK_SECONDS = 0.05
_HID_MODIFIER = "tessera_live_hid"  # on the object: the Subdivision modifier live mode hid, restored when it stops


def _current_view(window_manager):
    return active_viewport_view(window_manager)


# Where tick() reads the viewport's view from: the active 3D viewport. Blender recomputes a
# region's view matrix only when it draws, which background mode never does, so a headless test
# replaces this with a function returning the ViewportView a viewport move would leave there.
view_source = _current_view


@dataclass
class Job:
    """One send, read on Blender's thread and run on the worker's."""
    generation: int
    identifier: str
    cage: Cage
    same_topology_as: Optional[str]  # the mesh last uploaded, when this cage has its topology
    uvs_changed: bool                # since that mesh
    accuracy: Accuracy
    server: str
    token: str
    encoding: str
    display_name: str
    reasons: List[str]
    changed_at: float   # when the first change it carries was noticed (time.perf_counter)
    captured_at: float  # when tick() began reading the cage
    capture_s: float    # reading the cage and the view on Blender's thread
    timeout: float = 120.0


@dataclass
class Outcome:
    job: Job
    error: Optional[str] = None
    prepared: Optional[dict] = None
    summary: object = None
    glb_bytes: int = 0
    upload: str = ""
    upload_s: float = 0.0
    tessellate_s: float = 0.0
    decode_s: float = 0.0


class Worker:
    """A thread that runs one job at a time; a job submitted while one runs replaces the one
    waiting (the latest wins)."""

    def __init__(self):
        self._condition = threading.Condition()
        self._waiting: Optional[Job] = None
        self._busy = False
        self._stopping = False
        self._outcomes: List[Outcome] = []
        self._client, self._client_key = None, None
        self._thread = threading.Thread(target=self._run, name="tessera-live", daemon=True)
        self._thread.start()

    def submit(self, job: Job) -> None:
        with self._condition:
            self._waiting = job
            self._condition.notify()

    def idle(self) -> bool:
        with self._condition:
            return self._waiting is None and not self._busy

    def take_outcomes(self) -> List[Outcome]:
        with self._condition:
            outcomes, self._outcomes = self._outcomes, []
            return outcomes

    def stop(self) -> None:
        """The thread ends once a request under way is back; its outcome is dropped."""
        with self._condition:
            self._stopping = True
            self._waiting = None
            self._condition.notify()

    def _run(self) -> None:
        while True:
            with self._condition:
                while self._waiting is None and not self._stopping:
                    self._condition.wait()
                if self._stopping:
                    break
                job, self._waiting, self._busy = self._waiting, None, True
            outcome = self._perform(job)
            with self._condition:
                self._busy = False
                if not self._stopping:
                    self._outcomes.append(outcome)
        if self._client is not None:
            self._client.close()

    def _client_for(self, server: str, token: str):
        from tessera_client import TesseraClient  # noqa: PLC0415 (the client package is found at call time)
        if self._client_key != (server, token):
            if self._client is not None:
                self._client.close()
            self._client, self._client_key = TesseraClient(server, token=token or None), (server, token)
        return self._client

    def _perform(self, job: Job) -> Outcome:
        outcome = Outcome(job)
        try:
            client = self._client_for(job.server, job.token)
            start = time.perf_counter()
            outcome.upload = upload_cage(client, job.identifier, job.cage, job.display_name, job.timeout,
                                         same_topology_as=job.same_topology_as, uvs_changed=job.uvs_changed)
            uploaded = time.perf_counter()
            result = tessellate_cage(client, job.identifier, job.accuracy, job.encoding, job.timeout)
            tessellated = time.perf_counter()
            outcome.prepared = prepare_mesh(result.glb)
            outcome.summary, outcome.glb_bytes = result.summary, len(result.glb)
            outcome.upload_s, outcome.tessellate_s = uploaded - start, tessellated - uploaded
            outcome.decode_s = time.perf_counter() - tessellated
        except Exception as error:  # noqa: BLE001 (every failure is shown in the panel; the last result stays)
            outcome.error = str(as_tessera_error(error)) or type(error).__name__
        return outcome


@dataclass
class LiveSession:
    """Live mode's state for one object."""
    name: str
    pointer: int
    worker: Worker = field(default_factory=Worker)
    changed_at: Optional[float] = None   # first change not yet sent
    last_change: float = 0.0             # the latest change (the debounce counts from it)
    reasons: List[str] = field(default_factory=list)
    generation: int = 0
    sent_key: Optional[tuple] = None     # the last request sent: the cage's id and what was asked
    sent_signature: Optional[str] = None  # the topology signature of the last cage uploaded
    sent_identifier: Optional[str] = None
    sent_uvs: Optional[list] = None
    seen_view: object = None             # the viewport's view when tick() last looked
    applied: int = 0                     # the generation shown by `<name>_tessera`
    applied_job: Optional[Job] = None
    summary: object = None
    round_trip_s: float = 0.0
    error: Optional[str] = None
    history: List[dict] = field(default_factory=list)

    def note_change(self, reason: str) -> None:
        now = time.perf_counter()
        if self.changed_at is None:
            self.changed_at = now
        self.last_change = now
        if reason not in self.reasons:
            self.reasons.append(reason)

    def pending(self) -> bool:
        """A change not yet sent, or a request not yet back."""
        return self.changed_at is not None or not self.worker.idle()


_sessions: Dict[str, LiveSession] = {}


def session_of(obj) -> Optional[LiveSession]:
    return _sessions.get(obj.name)


def start(obj) -> LiveSession:
    """Live mode on for obj: its Subdivision modifier hidden in the viewport (`<name>_tessera`
    shows the surface; its input is then the evaluated object) and a first send."""
    session = _sessions.get(obj.name)
    if session is None:
        modifier = subdivision_modifier(obj)
        if modifier is not None and modifier.show_viewport:
            modifier.show_viewport = False
            obj[_HID_MODIFIER] = modifier.name
        session = _sessions[obj.name] = LiveSession(obj.name, obj.as_pointer())
    session.note_change("live")
    if not bpy.app.timers.is_registered(tick):
        bpy.app.timers.register(tick, first_interval=0.0)
    return session


def stop(obj) -> None:
    """Live mode off: the worker let go, the modifier shown again if live mode hid it."""
    session = _sessions.pop(obj.name, None)
    if session is not None:
        session.worker.stop()
    hidden = obj.get(_HID_MODIFIER)
    if hidden is not None:
        modifier = obj.modifiers.get(hidden)
        if modifier is not None:
            modifier.show_viewport = True
        del obj[_HID_MODIFIER]


def stop_all() -> None:
    for session in list(_sessions.values()):
        obj = _object_of(session)
        if obj is not None:
            stop(obj)
        else:
            session.worker.stop()
            _sessions.pop(session.name, None)


def _object_of(session: LiveSession):
    """The session's object: by name (an undo may have moved it in memory), else by address (it
    was renamed: the session follows it)."""
    obj = bpy.data.objects.get(session.name)
    if obj is None:
        obj = next((o for o in bpy.data.objects if o.as_pointer() == session.pointer), None)
        if obj is not None:
            _sessions.pop(session.name, None)
            session.name = obj.name
            _sessions[obj.name] = session
    if obj is not None:
        session.pointer = obj.as_pointer()
    return obj


def tick() -> Optional[float]:
    """The timer: results shown, the viewport watched, changes sent. Returns when to run again
    (None, no live object left: the timer ends)."""
    for session in list(_sessions.values()):
        obj = _object_of(session)
        if obj is None or not obj.tessera.live:
            if obj is not None:
                stop(obj)  # Live set off without its update callback (from a script)
            else:
                session.worker.stop()
                _sessions.pop(session.name, None)
            continue
        try:
            _tick_session(session, obj)
        except Exception as error:  # noqa: BLE001 (an exception would end Blender's timer: shown, and live goes on)
            traceback.print_exc()
            session.error = f"live mode: {type(error).__name__}: {error}"
    return TICK_SECONDS if _sessions else None


def _tick_session(session: LiveSession, obj) -> None:
    for outcome in session.worker.take_outcomes():
        _show(session, obj, outcome)
    target = bpy.data.objects.get(obj.name + "_tessera")
    if target is not None and target.matrix_world != obj.matrix_world:
        target.matrix_world = obj.matrix_world.copy()
    if obj.tessera.mode == "PIXEL":
        view = view_source(bpy.context.window_manager)
        if view != session.seen_view:
            session.seen_view = view
            session.note_change("view")
    preferences = bpy.context.preferences.addons[__package__].preferences
    if session.changed_at is None or not session.worker.idle() \
            or time.perf_counter() - session.last_change < preferences.live_debounce:
        return
    _send(session, obj, preferences)


def _send(session: LiveSession, obj, preferences) -> None:
    """Reads the evaluated cage and what is asked, and hands them to the worker, unless the server
    was asked exactly that last time."""
    captured_at = time.perf_counter()
    # Evaluating runs the depsgraph handler for what is still tagged (a property just set): those
    # changes are in this send.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    changed_at, reasons = session.changed_at, session.reasons
    session.changed_at, session.reasons = None, []
    settings = obj.tessera
    try:
        cage = evaluated_cage(obj, depsgraph)
        if not cage.face_sizes:
            raise TesseraError(f"{obj.name} has no faces")
        accuracy = Accuracy(settings.mode, settings.tolerance, settings.pixel_accuracy)
        if settings.mode == "PIXEL":
            view = session.seen_view
            accuracy.camera = viewport_camera(obj, view) if view is not None else scene_camera(bpy.context.scene, obj)
    except (CageError, TesseraError) as error:
        session.error = str(error)
        session.sent_key = None  # once it can be read again, it is sent (which clears the error)
        _redraw()
        return
    encoding = glb_encoding(preferences.server, preferences.encoding)
    identifier = mesh_id(cage)
    key = (identifier, accuracy.key(), encoding, preferences.server)
    if key == session.sent_key:
        return  # a frame or an update that left the cage as it was
    signature = topology_signature(cage)
    same_topology_as = session.sent_identifier if signature == session.sent_signature else None
    uvs_changed = cage.uvs != session.sent_uvs
    session.generation += 1
    session.sent_key, session.sent_signature, session.sent_identifier = key, signature, identifier
    session.sent_uvs = cage.uvs
    session.worker.submit(Job(session.generation, identifier, cage, same_topology_as, uvs_changed, accuracy,
                              preferences.server, preferences.token, encoding, obj.name, reasons, changed_at,
                              captured_at, time.perf_counter() - captured_at))


def _show(session: LiveSession, obj, outcome: Outcome) -> None:
    """A result in `<name>_tessera` (the same object, its mesh replaced), or its error in the
    panel with the last good result kept."""
    job = outcome.job
    record = {"generation": job.generation, "reasons": job.reasons, "mode": job.accuracy.mode,
              "same_topology": job.same_topology_as is not None, "uvs_changed": job.uvs_changed,
              "upload": outcome.upload,
              "capture_s": job.capture_s, "upload_s": outcome.upload_s, "tessellate_s": outcome.tessellate_s,
              "decode_s": outcome.decode_s}
    if outcome.error is not None:
        session.error = outcome.error  # the same request is not sent again until something changes
        record["error"] = outcome.error
    else:
        start = time.perf_counter()
        mesh = mesh_from(bpy, obj.name + "_tessera", outcome.prepared)
        place_result(bpy.context, obj, mesh, outcome.summary, job.encoding, outcome.glb_bytes)
        done = time.perf_counter()
        session.error, session.applied, session.applied_job, session.summary = None, job.generation, job, outcome.summary
        session.round_trip_s = done - job.captured_at
        record.update(triangles=outcome.summary.triangles, bound=outcome.summary.guaranteed_bound,
                      glb_bytes=outcome.glb_bytes, mesh_s=done - start, round_trip_s=done - job.captured_at,
                      since_change_s=done - job.changed_at)
    session.history.append(record)
    _redraw()


def _redraw() -> None:
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas if window.screen else ():
            if area.type in ("PROPERTIES", "VIEW_3D"):
                area.tag_redraw()


@persistent
def on_depsgraph_update(scene, depsgraph) -> None:
    """A live object's geometry changed (edit mode, sculpting, creases, UVs, modifiers above the
    Subdivision one, a driven deformation), or it moved (which changes the view of it)."""
    if not _sessions:
        return
    for update in depsgraph.updates:
        original = update.id.original
        if not isinstance(original, bpy.types.Object):
            continue
        if original == scene.camera and update.is_updated_transform:
            for session in _sessions.values():  # pixel mode without a 3D viewport follows the scene camera
                session.note_change("camera")
        session = _sessions.get(original.name)
        if session is None:
            continue
        if update.is_updated_geometry:
            session.note_change("geometry")
        elif update.is_updated_shading and original.mode == "SCULPT":
            session.note_change("sculpt")  # a stroke redraws through the sculpt's own buffers first
        elif update.is_updated_transform and original.tessera.mode == "PIXEL":
            session.note_change("transform")


@persistent
def on_frame_change(scene, depsgraph=None) -> None:
    """Shape keys and armatures move the cage on a frame change: the evaluated cage is read at the
    next tick (a frame that leaves it as it was sends nothing)."""
    for session in _sessions.values():
        session.note_change("frame")


@persistent
def on_undo(*_args) -> None:
    """An undo or redo may put back another cage (a send only if it did), or the Live toggle
    itself (set back without its update callback)."""
    for session in _sessions.values():
        session.note_change("undo")
    for obj in bpy.data.objects:
        if obj.type == "MESH" and obj.tessera.live and obj.name not in _sessions:
            start(obj)


@persistent
def on_load_pre(*_args) -> None:
    stop_all()


@persistent
def on_load_post(*_args) -> None:
    """A file saved with live objects: live mode starts again for them."""
    for obj in bpy.data.objects:
        if obj.type == "MESH" and obj.tessera.live:
            start(obj)


_HANDLERS = ((bpy.app.handlers.depsgraph_update_post, on_depsgraph_update),
             (bpy.app.handlers.frame_change_post, on_frame_change),
             (bpy.app.handlers.undo_post, on_undo),
             (bpy.app.handlers.redo_post, on_undo),
             (bpy.app.handlers.load_pre, on_load_pre),
             (bpy.app.handlers.load_post, on_load_post))


def register() -> None:
    for handlers, handler in _HANDLERS:
        if handler not in handlers:
            handlers.append(handler)


def unregister() -> None:
    stop_all()
    for handlers, handler in _HANDLERS:
        if handler in handlers:
            handlers.remove(handler)
    if bpy.app.timers.is_registered(tick):
        bpy.app.timers.unregister(tick)
