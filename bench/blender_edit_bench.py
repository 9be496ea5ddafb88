"""Run inside headless Blender by bench/blender_edit_table.py (issue 48, item 6): the cost of one
edit of a model's cage, for the add-on's live mode against a real tessera-server on loopback and
for Blender's own Subdivision Surface modifier at uniform levels, in the same Blender process,
alternated edit by edit.

The model's OBJ is read here (positions, faces, UVs and its `t crease` tags; Blender's OBJ
importer drops the tags) into one Blender mesh, given to two objects: "Tessera" (live mode on, a
relative tolerance) and "Modifier" (a Subdivision Surface modifier shown at level L, one object
per level asked, each a copy of the same mesh). Both see the same cage: the creases are Blender
edge creases sqrt(s / 10) for OBJ sharpness s (the add-on sends 10 c²), read back by the add-on
for Tessera and by the modifier (use_creases) for Blender.

One edit: one cage vertex moved (the same vertex and offset on every object, each object's just
before its own timing), then timed from before the depsgraph evaluation that follows the move:
- Modifier, level L: `view_layer.update()` (Blender evaluates the modifier, its OpenSubdiv
  topology kept from the last evaluation since the topology is unchanged) and the evaluated mesh
  taken (`evaluated_get(...).data`, its vertex count read so that the mesh exists on the CPU).
- Tessera: `view_layer.update()` (the add-on's handler notes the change), then the live timer's
  function (live.tick) called every 2 ms until `Tessera_tessera` holds the edit's mesh (the cage
  read, the positions-only upload, the tessellation, the GLB read and welded, the mesh built),
  then `view_layer.update()` again (the new mesh evaluated). Blender's own timer runs every 50 ms,
  which would add up to 50 ms; polling every 2 ms leaves that out.
Neither includes drawing. Two edits of each are made first (warm-up: the server keeps a topology
from its second patch set on, and the modifier builds its OpenSubdiv topology at its first
evaluation); REPS timed edits then follow, the order of Tessera and the modifiers swapped every
other edit.

Written to OUT_DIR: times.json (each edit's times, the add-on's record, the load average), the
cage as sent (cage.obj, Y-up, with its tags), Tessera's last mesh (tessera.obj) and each level's
last evaluated mesh (level-L.obj, its quads as two triangles) for tessera-limit-check.
Arguments after "--": OUT_DIR SERVER_BINARY MODEL.obj TOLERANCE LEVELS(comma-separated) REPS."""
import json
import math
import os
import statistics
import sys
import time
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "blender"))
from blender_session import enable_addon, start_server, write_cage  # noqa: E402

arguments = sys.argv[sys.argv.index("--") + 1:]
out, server_binary, model = Path(arguments[0]), arguments[1], Path(arguments[2])
tolerance, levels, reps = float(arguments[3]), [int(x) for x in arguments[4].split(",")], int(arguments[5])


def read_obj(path: Path):
    """Positions (Blender's Z-up, from the OBJ's Y-up), faces, the UV of every face corner and the
    creases (v0, v1, sharpness) of an OBJ with `t crease 2/1/0 V0 V1 S` tags (0-based)."""
    positions, uvs, faces, corner_uvs, creases = [], [], [], [], []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "v":
                x, y, z = (float(c) for c in fields[1:4])
                positions.append((x, -z, y))  # cage.from_y_up
            elif fields[0] == "vt":
                uvs.append((float(fields[1]), float(fields[2])))
            elif fields[0] == "f":
                corners = [c.split("/") for c in fields[1:]]
                faces.append([int(c[0]) - 1 for c in corners])
                corner_uvs.append([int(c[1]) - 1 if len(c) > 1 and c[1] else -1 for c in corners])
            elif fields[0] == "t":
                if fields[1] != "crease":
                    raise SystemExit(f"{path}: tag {fields[1]} is not read by this benchmark")
                creases.append((int(fields[3]), int(fields[4]), float(fields[5])))
    return positions, uvs, faces, corner_uvs, creases


def cage_mesh(name: str, path: Path):
    positions, uvs, faces, corner_uvs, creases = read_obj(path)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(positions, [], faces)
    mesh.validate(verbose=False)
    assert len(mesh.vertices) == len(positions) and len(mesh.polygons) == len(faces), "Blender changed the cage"
    if uvs:
        loops = np.array([uvs[i] if i >= 0 else (0.0, 0.0) for face in corner_uvs for i in face], dtype=np.float32)
        mesh.uv_layers.new(name="UVMap").data.foreach_set("uv", loops.reshape(-1))
    edge_of = {frozenset(e.vertices): e.index for e in mesh.edges}
    crease = np.zeros(len(mesh.edges), dtype=np.float32)
    for v0, v1, sharpness in creases:
        crease[edge_of[frozenset((v0, v1))]] = min(1.0, math.sqrt(sharpness / 10.0))
    mesh.edges.foreach_set("crease", crease)
    mesh.update()
    return mesh


def new_object(name: str, mesh, level: int):
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    modifier = obj.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = level
    modifier.uv_smooth = "PRESERVE_BOUNDARIES"  # Blender's default, as the add-on sends it
    return obj


def write_triangles(path: Path, mesh) -> None:
    """A Blender mesh's vertices (Y-up) and faces, each polygon as a fan of triangles."""
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    sizes = np.empty(len(mesh.polygons), dtype=np.int64)
    starts = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_total", sizes)
    mesh.polygons.foreach_get("loop_start", starts)
    loops = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", loops)
    triangles = []
    for k in range(1, int(sizes.max()) - 1):
        has = sizes > k + 1
        triangles.append(np.stack([loops[starts[has]], loops[starts[has] + k], loops[starts[has] + k + 1]], axis=1))
    triangles = np.concatenate(triangles) + 1
    with open(path, "w") as f:
        np.savetxt(f, np.stack([co[:, 0], co[:, 2], -co[:, 1]], axis=1), fmt="v %.9g %.9g %.9g")
        np.savetxt(f, triangles, fmt="f %d %d %d")


def main():
    process, address, _ = start_server(server_binary)
    try:
        preferences = enable_addon(address)
        preferences.live_debounce = 0.0
        from tessera_subdiv import live
        from tessera_subdiv.cage import read_cage
        view_layer = bpy.context.view_layer

        source = cage_mesh("Cage", model)
        tessera = new_object("Tessera", source.copy(), 1)
        modifiers = {level: new_object(f"Modifier-{level}", source.copy(), level) for level in levels}
        cage = read_cage(tessera)
        assert all(read_cage(m) == read_cage(tessera) for m in modifiers.values())
        lows, highs = np.array(cage.positions).reshape(-1, 3).min(0), np.array(cage.positions).reshape(-1, 3).max(0)
        diagonal = float(np.linalg.norm(highs - lows))
        tessera.tessera.mode, tessera.tessera.tolerance = "RELATIVE", tolerance
        view_layer.update()
        tessera.tessera.live = True
        session = live.session_of(tessera)

        def settle():
            while session.pending():
                live.tick()
                time.sleep(0.002)
            live.tick()

        settle()
        assert session.error is None, session.error

        def time_tessera():
            sends = len(session.history)
            start = time.perf_counter()
            view_layer.update()
            assert session.changed_at is not None, "live mode did not notice the edit"
            settle()
            view_layer.update()
            seconds = time.perf_counter() - start
            assert len(session.history) == sends + 1 and session.error is None, (session.error, session.history[-1])
            return seconds, dict(session.history[-1])

        def time_modifier(level):
            obj = modifiers[level]
            start = time.perf_counter()
            view_layer.update()
            evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
            vertices = len(evaluated.vertices)
            seconds = time.perf_counter() - start
            return seconds, vertices, len(evaluated.polygons)

        from mathutils import Vector
        step = 1e-3 * diagonal
        rng = np.random.default_rng(48)
        edits = []
        for rep in range(reps + 2):
            index = int(rng.integers(len(source.vertices)))
            offset = Vector(rng.normal(size=3)).normalized() * step
            edit = {"rep": rep - 2, "vertex": index, "load_before": os.getloadavg()[0]}
            order = ["tessera"] + levels if rep % 2 == 0 else levels + ["tessera"]
            for what in order:
                # Each object's cage moved just before its own timing: the depsgraph evaluates
                # every object tagged, so moving all first would time them together.
                obj = tessera if what == "tessera" else modifiers[what]
                obj.data.vertices[index].co += offset
                obj.data.update()
                if what == "tessera":
                    edit["tessera_s"], edit["record"] = time_tessera()
                else:
                    edit[f"level_{what}_s"], vertices, faces = time_modifier(what)
                    edit[f"level_{what}_faces"] = faces
            edit["load_after"] = os.getloadavg()[0]
            edits.append(edit)
            record = edit["record"]
            print(f"{model.stem} edit {rep - 2}: tessera {1000 * edit['tessera_s']:.0f} ms "
                  f"(upload {record['upload']} {1000 * record['upload_s']:.0f}, tessellate "
                  f"{1000 * record['tessellate_s']:.0f}, GLB {1000 * record['decode_s']:.0f}, mesh "
                  f"{1000 * record['mesh_s']:.0f}; {record['triangles']} triangles), " +
                  ", ".join(f"level {level} {1000 * edit[f'level_{level}_s']:.0f} ms" for level in levels) +
                  f"; load {edit['load_before']:.1f}")
        timed = [e for e in edits if e["rep"] >= 0]
        assert all(e["record"]["upload"] == "positions" for e in timed), [e["record"]["upload"] for e in timed]
        summary = {"model": model.stem, "tolerance": tolerance, "diagonal": diagonal, "reps": reps,
                   "cage_vertices": len(source.vertices), "cage_faces": len(source.polygons),
                   "tessera_median_s": statistics.median(e["tessera_s"] for e in timed),
                   "tessera_triangles": timed[-1]["record"]["triangles"],
                   "tessera_bound": timed[-1]["record"]["bound"],
                   "levels": {level: {"median_s": statistics.median(e[f"level_{level}_s"] for e in timed),
                                      "faces": timed[-1][f"level_{level}_faces"]} for level in levels},
                   "parts_median_s": {part: statistics.median(e["record"][part] for e in timed)
                                      for part in ("capture_s", "upload_s", "tessellate_s", "decode_s", "mesh_s",
                                                   "round_trip_s")},
                   "load_average": [min(e["load_before"] for e in timed), max(e["load_after"] for e in timed)],
                   "edits": edits, "blender": bpy.app.version_string}
        (out / "times.json").write_text(json.dumps(summary, indent=1))
        write_cage(out / "cage.obj", session.applied_job.cage)
        from blender_session import write_result
        from tessera_subdiv.cage import to_y_up
        write_result(out / "tessera.obj", bpy.data.objects["Tessera_tessera"].data, to_y_up)
        assert session.applied_job.cage == read_cage(modifiers[levels[0]]), "the objects' cages differ"
        depsgraph = bpy.context.evaluated_depsgraph_get()
        for level, obj in modifiers.items():
            write_triangles(out / f"level-{level}.obj", obj.evaluated_get(depsgraph).data)
        tessera.tessera.live = False
        live.tick()
    finally:
        process.terminate()
        process.wait(timeout=30)


main()
