"""Run inside headless Blender by tests/blender/run_live.sh: the add-on's live mode against a real
tessera-server. A creased, UV-mapped cube with a Subdivision modifier goes live; ten vertex moves
in edit mode through bmesh, one crease change, a shape-key animation over five frames, a move of
the 3D viewport's view in pixel mode, a refused request and a return to a relative tolerance each
reach `Cage_tessera`, the same object each time with its mesh replaced (its material and modifier
kept). The position-only edits are uploaded positions-only and take the server's topology-reuse
path (its /metrics); when the mesh they name is gone they are uploaded whole. Per-edit
round trips go to OUT_DIR/live-round-trips.json, and the last cage sent and the final mesh are
written (Y-up, as sent) for tessera-limit-check, as is the pixel-mode result with its bound.

What background mode changes, and how the test stands in for it:
- Blender's timers do not fire without an event loop: the test calls live.tick(), the function
  the add-on registers with bpy.app.timers, in a loop, as the timer would every 50 ms.
- Blender evaluates the depsgraph after an operator or an edit in its event loop: the test calls
  view_layer.update(), which evaluates it and runs the add-on's depsgraph handler;
  scene.frame_set() runs the frame-change handler as playback does.
- A 3D viewport's view matrix is recomputed only when Blender draws it, which background mode
  never does: the first pixel-mode request reads the real viewport of the startup layout through
  the add-on's own reader (viewport.active_viewport_view); the move is a ViewportView built from
  it (the same field of view and size, the eye four times closer) given to tick() through
  live.view_source, where the reader's result goes. Noticing the move, the camera conversion and
  the send are the add-on's own code.
Arguments after "--": OUT_DIR SERVER_BINARY."""
import dataclasses
import json
import math
import sys
import time
from pathlib import Path

import bmesh
import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
from blender_session import (creased_cube, enable_addon, metric, panel_labels, start_server,  # noqa: E402
                             write_cage, write_result)

out, server_binary = Path(sys.argv[sys.argv.index("--") + 1]), sys.argv[sys.argv.index("--") + 2]
TOLERANCE, UV_RULE = 1e-3, ("PRESERVE_BOUNDARIES", "boundaries")
HITS, BUILT = "tessera_topology_cache_hits_total", "tessera_topology_cache_misses_total"
UPLOADED = "tessera_upload_bytes_total"  # the uploads' data bytes as the server counts them


class Live:
    """Drives live mode as Blender's event loop would, and checks each update."""

    def __init__(self, cube, live_module, metrics_address):
        self.cube, self.live, self.metrics = cube, live_module, metrics_address
        self.session = live_module.session_of(cube)
        self.target = None
        self.tick_seconds = []

    def tick(self):
        start = time.perf_counter()
        self.live.tick()
        self.tick_seconds.append(time.perf_counter() - start)

    def settle(self, timeout=60.0):
        """Ticks until nothing is waiting to be sent or to come back."""
        deadline = time.monotonic() + timeout
        self.tick()
        while self.session.pending():
            assert time.monotonic() < deadline, "live mode did not settle"
            time.sleep(0.005)
            self.tick()

    def update(self, what, expect_error=None):
        """After a change the handlers noticed: ticks until its result is in `Cage_tessera` (the
        same object, a new mesh) and returns the send's record."""
        sends = len(self.session.history)
        before = self.target.data.as_pointer() if self.target else None
        self.settle()
        assert len(self.session.history) == sends + 1, f"{what}: {len(self.session.history) - sends} sends"
        record = dict(self.session.history[-1], edit=what)
        target = bpy.data.objects["Cage_tessera"]
        if expect_error:
            assert expect_error in self.session.error, (what, self.session.error)
            assert target.data.as_pointer() == before, f"{what}: the last good mesh was not kept"
        else:
            assert self.session.error is None, (what, self.session.error)
            if self.target is not None:
                assert target.as_pointer() == self.target.as_pointer(), f"{what}: a new object"
                assert target.data.as_pointer() != before, f"{what}: the mesh was not replaced"
            self.target = target
            assert len(target.data.polygons) == record["triangles"] == target["tessera_triangles"], what
        print(f"{what}: {record.get('triangles', '-')} triangles, round trip "
              f"{1000 * record.get('round_trip_s', 0):.1f} ms (upload {1000 * record['upload_s']:.1f}, "
              f"tessellate {1000 * record['tessellate_s']:.1f}, GLB read {1000 * record['decode_s']:.1f}, "
              f"mesh {1000 * record.get('mesh_s', 0):.1f}), same topology {record['same_topology']}")
        return record

    def noticed(self, what):
        """The add-on's handlers (not the test) registered the change."""
        assert self.session.changed_at is not None, f"{what}: the handlers did not notice the change"


def edit_mesh(cube, change):
    """A change made through bmesh on the edit mesh, as an edit-mode tool makes it, then the
    depsgraph evaluated (the event loop's part)."""
    mesh = bmesh.from_edit_mesh(cube.data)
    mesh.verts.ensure_lookup_table()
    mesh.edges.ensure_lookup_table()
    change(mesh)
    bmesh.update_edit_mesh(cube.data)
    bpy.context.view_layer.update()


def move_vertex(index, offset):
    def change(mesh):
        mesh.verts[index].co += offset
    return change


def crease_an_edge(mesh):
    """The first edge without a crease gets 0.5 (sharpness 2.5)."""
    layer = mesh.edges.layers.crease.verify()
    next(e for e in mesh.edges if e[layer] == 0)[layer] = 0.5


def shift_uvs_of_a_vertex(mesh):
    """Every corner of vertex 0 that carries its first UV moves with it: new UV values, the same
    UV indices."""
    layer = mesh.loops.layers.uv.active
    corners = [loop for loop in mesh.verts[0].link_loops]
    first = corners[0][layer].uv.copy()
    for loop in corners:
        if loop[layer].uv == first:
            loop[layer].uv += Vector((0.01, 0.02))


def topology_counters(metrics_address):
    return metric(metrics_address, HITS), metric(metrics_address, BUILT)


def check_reuse(what, before, after, sends):
    """Every tessellation of a cage uploaded positions-only reused the topology: the upload keeps
    it (docs/DECISIONS.md, "Edits reuse topology"), built once at the first such upload unless the
    server kept it already."""
    hits, built = after[0] - before[0], after[1] - before[1]
    print(f"{what}: {sends} sends, topology cache hits {hits:g}, topologies built {built:g}")
    assert hits == sends and built <= 1, (what, hits, built, sends)
    return {"sends": sends, "topology_cache_hits": hits, "topologies_built": built}


def look_at(eye: Vector, target: Vector) -> Matrix:
    """A view matrix (world to view, looking down -Z, +Z of the world up on screen)."""
    view_to_world = (target - eye).to_track_quat("-Z", "Y").to_matrix().to_4x4()
    view_to_world.translation = eye
    return view_to_world.inverted()


def main():
    process, address, metrics_address = start_server(server_binary)
    try:
        preferences = enable_addon(address)
        from tessera_subdiv import live
        from tessera_subdiv.cage import read_cage, to_y_up
        from tessera_subdiv.viewport import active_viewport_view
        from tessera_subdiv.request import mesh_id, upload_cage
        from tessera_client import TesseraClient
        preferences.live_debounce = 0.02
        cube = creased_cube(UV_RULE[0])
        cube.tessera.tolerance = TOLERANCE
        report = {"server": "tessera-server on loopback", "tolerance": TOLERANCE}

        # Live on: the Subdivision modifier hidden (its result is Cage_tessera), a first send.
        cube.tessera.live = True
        assert not cube.modifiers["Subdivision"].show_viewport
        driver = Live(cube, live, metrics_address)
        records = [driver.update("live on")]
        # The evaluated cage live mode read is the one the button reads from the object's mesh.
        assert driver.session.applied_job.cage == read_cage(cube), "the evaluated cage differs from the mesh's"
        assert driver.session.applied_job.cage.corners and len(driver.session.applied_job.cage.creases) == 4
        target = driver.target
        material = bpy.data.materials.new("Kept")
        target.data.materials.append(material)
        target.modifiers.new("Kept", "WEIGHTED_NORMAL")

        # Ten vertex moves in edit mode: the same topology each time, which the server reuses.
        bpy.context.view_layer.objects.active = cube  # the panel draws the active object's
        bpy.ops.object.mode_set(mode="EDIT")
        driver.settle()  # entering edit mode leaves the cage as it was: nothing is sent
        # Each is uploaded positions-only on the last mesh's topology: the server counts the
        # positions' bytes and nothing else (8 vertices, 3 float32 each).
        before = topology_counters(metrics_address)
        for i in range(10):
            uploaded = metric(metrics_address, UPLOADED)
            edit_mesh(cube, move_vertex(i % 8, Vector((0.02, -0.03, 0.05)) * (1 + i % 3)))
            driver.noticed(f"move {i + 1}")
            record = driver.update(f"move {i + 1}")
            assert record["same_topology"] and not record["uvs_changed"] and record["upload"] == "positions", record
            sent = driver.session.applied_job.cage
            assert metric(metrics_address, UPLOADED) - uploaded == 4 * len(sent.positions) == 96, \
                (metric(metrics_address, UPLOADED) - uploaded, len(sent.positions))
            records.append(record)
        report["moves"] = check_reuse("ten moves", before, topology_counters(metrics_address), 10)

        # The mesh an edit's upload names is gone from the server (deleted by another client): the
        # positions-only upload is refused NOT_FOUND and the whole cage is sent instead.
        client = TesseraClient(address)
        client.delete_mesh(driver.session.sent_identifier)
        edit_mesh(cube, move_vertex(3, Vector((0.01, 0.02, -0.01))))
        driver.noticed("move, its parent deleted")
        record = driver.update("move, its parent deleted")
        assert record["same_topology"] and record["upload"] == "full", record
        records.append(record)
        # A mesh whose counts differ (INVALID_ARGUMENT from the server): the whole cage too, stored
        # with its own vertex count. And a cage the server has: nothing sent.
        client.upload_arrays("one-quad", [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], [4], [0, 1, 2, 3])
        sent = driver.session.applied_job.cage
        moved = dataclasses.replace(sent, positions=[c + 0.25 for c in sent.positions])
        assert upload_cage(client, mesh_id(moved), moved, "Cage", 30.0, same_topology_as="one-quad",
                           uvs_changed=False) == "full"
        assert client.get_mesh(mesh_id(moved)).vertex_count == 8
        assert upload_cage(client, mesh_id(sent), sent, "Cage", 30.0, same_topology_as=mesh_id(moved),
                           uvs_changed=False) == "none"

        # A UV edit: new UV values on the same topology, carried by the positions-only upload,
        # whose preprocessing reuses it too.
        before = topology_counters(metrics_address)
        uploaded = metric(metrics_address, UPLOADED)
        edit_mesh(cube, shift_uvs_of_a_vertex)
        driver.noticed("UV edit")
        record = driver.update("UV edit")
        assert record["same_topology"] and record["uvs_changed"] and record["upload"] == "positions", record
        sent = driver.session.applied_job.cage
        assert metric(metrics_address, UPLOADED) - uploaded == 4 * (len(sent.positions) + len(sent.uvs)), \
            "the UV edit's upload is not its positions and UVs"
        report["uv_edit"] = check_reuse("UV edit", before, topology_counters(metrics_address), 1)
        assert report["uv_edit"]["topology_cache_hits"] == 1
        records.append(record)

        # One crease change: a new topology, built.
        before = topology_counters(metrics_address)
        edit_mesh(cube, crease_an_edge)
        driver.noticed("crease")
        record = driver.update("crease")
        assert not record["same_topology"] and record["upload"] == "full", record
        assert topology_counters(metrics_address)[1] == before[1] + 1, "the creased cage's topology was not built"
        records.append(record)
        creases = len(live.session_of(cube).applied_job.cage.creases)
        bpy.ops.object.mode_set(mode="OBJECT")
        driver.settle()  # leaving edit mode writes the same cage to the mesh: nothing is sent
        assert len(driver.session.history) == len(records), "leaving edit mode sent the cage again"

        # A shape key animated over frames 1-5 (value 0 at frame 0, 1 at frame 5): each frame's
        # evaluated cage is sent, its topology unchanged.
        scene = bpy.context.scene
        scene.frame_set(0)
        cube.shape_key_add(name="Basis")
        key = cube.shape_key_add(name="Pull")
        for point in key.data:
            if point.co.z > 0:
                point.co += Vector((0.4, 0.0, 0.6))
        key.value = 0.0
        key.keyframe_insert("value", frame=0)
        key.value = 1.0
        key.keyframe_insert("value", frame=5)
        scene.frame_set(0)
        driver.settle()  # the shape key at 0 leaves the cage as it was
        before = topology_counters(metrics_address)
        for frame in range(1, 6):
            scene.frame_set(frame)
            driver.noticed(f"frame {frame}")
            record = driver.update(f"frame {frame}")
            assert record["same_topology"] and "frame" in record["reasons"] and record["upload"] == "positions", record
            records.append(record)
        report["frames"] = check_reuse("five frames", before, topology_counters(metrics_address), 5)
        # The cage sent at frame 5 is the shape key's, value 1 (Blender's data, read independently).
        sent = live.session_of(cube).applied_job.cage
        expected = [c for point in key.data for c in to_y_up(*point.co)]
        assert max(abs(a - b) for a, b in zip(sent.positions, expected)) < 1e-6, "the sent cage is not frame 5's"
        assert len(sent.creases) == creases

        # An armature: its modifier added below the Subdivision one is refused (the error shown,
        # the last mesh kept); moved above it, the cage is sent again; a pose moves the cage.
        armature = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
        scene.collection.objects.link(armature)
        bpy.context.view_layer.objects.active = armature
        bpy.ops.object.mode_set(mode="EDIT")
        bone = armature.data.edit_bones.new("Bone")
        bone.head, bone.tail = (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)
        bpy.ops.object.mode_set(mode="OBJECT")
        cube.vertex_groups.new(name="Bone").add(range(len(cube.data.vertices)), 1.0, "REPLACE")
        cube.modifiers.new("Armature", "ARMATURE").object = armature
        shown = driver.target.data.as_pointer()
        bpy.context.view_layer.update()
        driver.noticed("armature below")
        driver.settle()
        assert "Subdivision modifier last" in driver.session.error, driver.session.error
        assert driver.target.data.as_pointer() == shown and len(driver.session.history) == len(records)
        bpy.context.view_layer.objects.active = cube
        bpy.ops.object.modifier_move_to_index(modifier="Armature", index=0)
        bpy.context.view_layer.update()
        driver.noticed("armature above")
        records.append(driver.update("armature above the Subdivision modifier"))
        rest = list(driver.session.applied_job.cage.positions)
        before = topology_counters(metrics_address)
        armature.pose.bones["Bone"].location = (0.3, 0.2, -0.1)  # the bone's frame: +Y along its length
        bpy.context.view_layer.update()
        driver.noticed("pose")
        record = driver.update("armature posed")
        assert record["same_topology"] and record["upload"] == "positions", record
        report["pose"] = check_reuse("pose", before, topology_counters(metrics_address), 1)
        records.append(record)
        # Every vertex moved by the bone's head, from the armature's frame to the cube's, Y-up.
        pose = armature.pose.bones["Bone"]
        offset = cube.matrix_world.inverted().to_3x3() @ (armature.matrix_world.to_3x3() @
                                                           (pose.head - pose.bone.head_local))
        offset = to_y_up(*offset)
        posed = driver.session.applied_job.cage.positions
        assert max(abs(p - r - offset[i % 3]) for i, (p, r) in enumerate(zip(posed, rest))) < 1e-5, offset

        # Pixel mode: the active viewport's view (the startup layout's, read by the add-on), then
        # the view four times closer: more triangles for the same cage.
        cube.tessera.mode = "PIXEL"
        startup_view = active_viewport_view(bpy.context.window_manager)
        assert startup_view is not None and startup_view.perspective, "the startup layout has no 3D viewport"
        far = driver.update("pixel mode, the viewport's view")
        assert driver.session.seen_view == startup_view
        # The camera sent, against the viewport's own navigation state: the eye at view_distance
        # behind view_location along the view rotation's +Z, and the field of view of Blender's
        # viewport lens (a 72 mm sensor across the wider side: 36 mm at zoom 2).
        area = next(a for w in bpy.context.window_manager.windows for a in w.screen.areas if a.type == "VIEW_3D")
        space = area.spaces.active
        region_3d = space.region_3d
        eye_world = region_3d.view_location + region_3d.view_rotation @ Vector((0.0, 0.0, region_3d.view_distance))
        sent_camera = driver.session.applied_job.accuracy.camera
        expected_eye = to_y_up(*(cube.matrix_world.inverted() @ eye_world))
        assert max(abs(a - b) for a, b in zip(sent_camera.eye, expected_eye)) < 1e-3, (sent_camera.eye, expected_eye)
        region = next(r for r in area.regions if r.type == "WINDOW")
        half_wide = math.atan(36.0 / space.lens)
        half_y = half_wide if region.height > region.width else \
            math.atan(math.tan(half_wide) * region.height / region.width)
        assert abs(sent_camera.fov_y_deg - math.degrees(2 * half_y)) < 1e-3, (sent_camera.fov_y_deg, half_y)
        assert (sent_camera.width, sent_camera.height) == (region.width, region.height)
        eye = Matrix([startup_view.view_matrix[i:i + 4] for i in (0, 4, 8, 12)]).inverted().translation
        centre = cube.matrix_world @ Vector((0.0, 0.0, 0.0))
        closer = look_at(centre + (eye - centre) / 4, centre)
        moved = dataclasses.replace(startup_view, view_matrix=tuple(c for row in closer for c in row))
        live.view_source = lambda window_manager: moved
        near = driver.update("viewport moved closer")
        assert "view" in near["reasons"] and near["upload"] == "none", near
        assert near["triangles"] > 2 * far["triangles"], (far["triangles"], near["triangles"])
        records += [far, near]
        write_cage(out / "pixel-cage.obj", driver.session.applied_job.cage)
        write_result(out / "pixel-result.obj", driver.target.data, to_y_up)
        (out / "pixel-bound").write_text(repr(near["bound"]))
        live.view_source = live._current_view  # noqa: SLF001

        # A request the server refuses: its message shown, the last good mesh kept.
        cube.tessera.mode, cube.tessera.tolerance = "RELATIVE", 1e-9
        driver.update("refused tolerance", expect_error="min_relative_tolerance")
        labels = [text for text, _ in panel_labels()]
        assert any("min_relative_tolerance" in label for label in labels), labels
        # Back to the tolerance: the final mesh, measured by run_live.sh.
        cube.tessera.tolerance = TOLERANCE
        records.append(driver.update("relative again"))
        assert driver.session.error is None
        # The panel: triangles, the proven bound and the round trip of what Cage_tessera shows.
        labels = [text for text, _ in panel_labels()]
        summary = driver.session.summary
        assert f"{summary.triangles:,} triangles, within {summary.guaranteed_bound:.3g}" in labels, labels
        assert f"Round trip {1000 * driver.session.round_trip_s:.0f} ms" in labels, labels
        print("panel:", labels)

        target = bpy.data.objects["Cage_tessera"]
        assert target.data.materials[:] == [material] and "Kept" in target.modifiers
        assert [m.name for m in bpy.data.meshes].count(target.data.name) == 1
        assert not [m for m in bpy.data.meshes if m.users == 0], "replaced meshes were left behind"
        write_cage(out / "cage.obj", driver.session.applied_job.cage)
        write_result(out / "result.obj", target.data, to_y_up)
        (out / "tolerance").write_text(repr(TOLERANCE))
        (out / "uv-interpolation").write_text(UV_RULE[1])

        # Live off: the modifier shown again, the worker let go.
        cube.tessera.live = False
        assert cube.modifiers["Subdivision"].show_viewport and live.session_of(cube) is None

        report["edits"] = records
        report["longest_tick_s"] = max(driver.tick_seconds)
        trips = sorted(r["round_trip_s"] for r in records)
        report["round_trip_median_s"] = trips[len(trips) // 2]
        (out / "live-round-trips.json").write_text(json.dumps(report, indent=1))
        print(f"live: {len(records)} updates, round trip median {1000 * trips[len(trips) // 2]:.1f} ms, "
              f"max {1000 * trips[-1]:.1f} ms; longest tick {1000 * max(driver.tick_seconds):.1f} ms")
    finally:
        process.terminate()
        process.wait(timeout=30)


main()
