"""Run inside headless Blender by tests/blender/run.sh: a creased, UV-mapped cube with a
Subdivision modifier goes to a real tessera-server through the add-on as a user enables it, comes
back as a new object beside it (triangles as the server counted them, UVs, custom normals, sharp
creases, the cage's transform), a failing request leaves that object as it was and reports the
server's message, pixel accuracy follows the scene camera, an edit that moves vertices takes the
server's topology-reuse path (its /metrics), a meshopt GLB is decoded by the add-on, and the edited
cage and the result (decoded from meshopt) are written (Y-up, as sent) for tessera-limit-check.
Arguments after "--": OUT_DIR SERVER_BINARY."""
import sys
from pathlib import Path

import bmesh
import bpy
from mathutils import Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
from blender_session import creased_cube, enable_addon, metric, start_server, write_obj  # noqa: E402

out, server_binary = Path(sys.argv[sys.argv.index("--") + 1]), sys.argv[sys.argv.index("--") + 2]
TOLERANCE, UV_RULE = 1e-3, ("PRESERVE_BOUNDARIES", "boundaries")


def main():
    process, address, metrics_address = start_server(server_binary)
    try:
        preferences = enable_addon(address)
        import tessera_subdiv
        from tessera_subdiv.cage import read_cage, to_y_up
        cube = creased_cube(UV_RULE[0], vertical_crease=0.6)
        cage = read_cage(cube)
        assert len(cage.creases) == 5 and cage.corners and cage.uv_indices and cage.uv_interpolation == UV_RULE[1], cage

        # Through the operator, as the panel's button runs it.
        bpy.context.view_layer.objects.active = cube
        cube.tessera.tolerance = TOLERANCE
        assert bpy.ops.object.tessera_tessellate() == {"FINISHED"}
        result = bpy.data.objects["Cage_tessera"]
        mesh = result.data
        assert len(mesh.polygons) == result["tessera_triangles"] > 100, (len(mesh.polygons), result["tessera_triangles"])
        assert mesh.uv_layers.active is not None and mesh.has_custom_normals
        assert any(e.use_edge_sharp for e in mesh.edges), "the creased rim came back without sharp edges"
        assert all(abs(a - b) < 1e-6 for r, s in zip(result.matrix_world, cube.matrix_world) for a, b in zip(r, s))
        assert result.users_collection[0] == cube.users_collection[0]

        # A request the server refuses: its message reaches the caller, the object keeps its mesh.
        try:
            tessera_subdiv.tessellate_object(bpy.context, cube, address, tolerance=1e-9)
            raise AssertionError("a tolerance finer than the server allows was accepted")
        except tessera_subdiv.TesseraError as error:
            assert "min_relative_tolerance" in str(error), str(error)
        assert bpy.data.objects["Cage_tessera"].data == mesh
        # The operator reports it as an error (which headless Blender raises), the object unchanged.
        cube.tessera.tolerance = 1e-9
        try:
            bpy.ops.object.tessera_tessellate()
            raise AssertionError("the operator accepted a tolerance finer than the server allows")
        except RuntimeError as error:
            assert "Tessera: relative: a tolerance" in str(error), str(error)
        assert bpy.data.objects["Cage_tessera"].data == mesh

        # Pixel accuracy for the scene camera: a camera ten times farther needs far fewer triangles.
        counts = []
        for distance in (6.0, 60.0):
            camera = bpy.data.objects.new(f"Camera{distance:g}", bpy.data.cameras.new("Camera"))
            bpy.context.scene.collection.objects.link(camera)
            camera.location = cube.location + Vector((0.0, -distance, 0.5 * distance))
            camera.rotation_euler = (cube.location - camera.location).to_track_quat("-Z", "Y").to_euler()
            bpy.context.scene.camera = camera
            cube.tessera.mode = "PIXEL"
            assert bpy.ops.object.tessera_tessellate() == {"FINISHED"}
            counts.append(bpy.data.objects["Cage_tessera"]["tessera_triangles"])
        assert counts[0] > 4 * counts[1] > 0, counts
        cube.tessera.mode, cube.tessera.tolerance = "RELATIVE", TOLERANCE
        assert bpy.ops.object.tessera_tessellate() == {"FINISHED"}

        # An edit that moves vertices (a corner pulled out): new content, the same topology, which
        # the server reuses (docs/DECISIONS.md "Edits reuse topology") and no new topology built.
        hits = metric(metrics_address, "tessera_topology_cache_hits_total")
        built = metric(metrics_address, "tessera_topology_cache_misses_total")
        edit = bmesh.new()
        edit.from_mesh(cube.data)
        corner = max(edit.verts, key=lambda v: v.co.x + v.co.y + v.co.z)
        corner.co += Vector((0.3, 0.2, 0.4))
        edit.to_mesh(cube.data)
        edit.free()
        cage = read_cage(cube)
        assert bpy.ops.object.tessera_tessellate() == {"FINISHED"}
        assert metric(metrics_address, "tessera_topology_cache_hits_total") == hits + 1
        assert metric(metrics_address, "tessera_topology_cache_misses_total") == built
        result = bpy.data.objects["Cage_tessera"]
        assert result["tessera_encoding"] == "float", "a loopback server is asked for float GLBs"
        float_bytes = result["tessera_glb_bytes"]

        # The same request as a meshopt GLB, decoded by the add-on: the result measured below against
        # OpenSubdiv's limit surface of the edited cage.
        preferences.encoding = "MESHOPT"
        assert bpy.ops.object.tessera_tessellate() == {"FINISHED"}
        result = bpy.data.objects["Cage_tessera"]
        mesh = result.data
        assert result["tessera_encoding"] == "meshopt"
        assert len(mesh.polygons) == result["tessera_triangles"], (len(mesh.polygons), result["tessera_triangles"])
        assert mesh.uv_layers.active is not None and any(e.use_edge_sharp for e in mesh.edges)
        print(f"GLB bytes: float {float_bytes}, meshopt {result['tessera_glb_bytes']}")
        assert result["tessera_glb_bytes"] < 0.6 * float_bytes

        # The cage as sent and the result in the same (Y-up) frame, for tessera-limit-check.
        faces, offset = [], 0
        for size in cage.face_sizes:
            faces.append(cage.face_vertices[offset:offset + size])
            offset += size
        corner_uvs, offset = [], 0
        for size in cage.face_sizes:
            corner_uvs.append(cage.uv_indices[offset:offset + size])
            offset += size
        write_obj(out / "cage.obj", cage.positions, faces, cage.uvs, corner_uvs, cage.creases,
                  [(v, s) for v, s in cage.corners])
        positions = [c for v in mesh.vertices for c in to_y_up(*v.co)]
        uvs, result_faces, result_uvs = [], [], []
        layer = mesh.uv_layers.active.data
        for polygon in mesh.polygons:
            result_faces.append(list(polygon.vertices))
            result_uvs.append([])
            for loop in range(polygon.loop_start, polygon.loop_start + polygon.loop_total):
                result_uvs[-1].append(len(uvs) // 2)
                uvs.extend(layer[loop].uv)
        write_obj(out / "result.obj", positions, result_faces, uvs, result_uvs)
        (out / "tolerance").write_text(repr(TOLERANCE))
        (out / "uv-interpolation").write_text(UV_RULE[1])
        print("round trip:", len(mesh.polygons), "triangles")
    finally:
        process.terminate()
        process.wait(timeout=30)


main()
