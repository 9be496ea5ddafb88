"""The Python client (client/python) against the real tessera-server on loopback, installed from a
wheel as a user would (tests/python/run.sh). References are independent of the client: the GLB is
parsed here with the standard library (its triangle count against the server's summary, its
positions against the uploaded cage's box), the canonical checksum is compared with the server's,
and retries are observed from the server's busy refusals."""
import json
import os
import struct
import subprocess
import tempfile
import threading
import time
import unittest
from pathlib import Path

import grpc
import numpy as np

from tessera_client import (Camera, IntegrityError, InvalidArgumentError, TesseraClient, TesseraError, canonical_sha256,
                            mesh_id)
from tessera_client._proto.tessera.v1 import mesh_pb2

SERVER = os.environ["TESSERA_SERVER_BINARY"]
SAMPLE = Path(os.environ["TESSERA_SAMPLE_OBJ"])


class Server:
    """tessera-server on 127.0.0.1 with a scratch SQLite store."""

    def __init__(self, *flags: str):
        self.dir = tempfile.TemporaryDirectory()
        ready = Path(self.dir.name) / "ready"
        self.process = subprocess.Popen(
            [SERVER, "--listen", "127.0.0.1:0", "--store", f"sqlite:{self.dir.name}/tessera.db",
             "--metrics-listen", "off", "--ready-file", str(ready), "--log-level", "warn", *flags])
        for _ in range(200):
            if ready.exists() and "grpc=" in ready.read_text():
                break
            if self.process.poll() is not None:
                raise RuntimeError(f"tessera-server exited with {self.process.returncode}")
            time.sleep(0.05)
        self.address = next(line[5:] for line in ready.read_text().splitlines() if line.startswith("grpc="))

    def stop(self) -> None:
        self.process.terminate()
        self.process.wait(timeout=30)
        self.dir.cleanup()


def glb_triangles_and_box(glb: bytes):
    """Triangle count and position bounds of a GLB's first primitive, read with the standard library."""
    magic, _version, length = struct.unpack_from("<4sII", glb, 0)
    assert magic == b"glTF" and length == len(glb)
    json_length, json_type = struct.unpack_from("<I4s", glb, 12)
    assert json_type == b"JSON"
    document = json.loads(glb[20:20 + json_length])
    primitive = document["meshes"][0]["primitives"][0]
    indices = document["accessors"][primitive["indices"]]
    position = document["accessors"][primitive["attributes"]["POSITION"]]
    return indices["count"] // 3, position["min"], position["max"], document


def cage_box(obj: Path):
    vertices = np.array([[float(x) for x in line.split()[1:4]] for line in obj.read_text().splitlines()
                         if line.startswith("v ")])
    return vertices.min(axis=0), vertices.max(axis=0)


def grid_arrays(n: int):
    """An n × n grid of quads on z = 0 with a crease along its middle row of edges."""
    positions = np.array([[x, y, 0.0] for y in range(n + 1) for x in range(n + 1)], dtype=np.float32)
    faces = np.array([[y * (n + 1) + x, y * (n + 1) + x + 1, (y + 1) * (n + 1) + x + 1, (y + 1) * (n + 1) + x]
                      for y in range(n) for x in range(n)], dtype=np.int32)
    middle = n // 2 * (n + 1)
    creases = [(middle + x, middle + x + 1, 2.5) for x in range(n)]
    return positions, np.full(n * n, 4, dtype=np.int32), faces, creases


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server()
        cls.client = TesseraClient(cls.server.address)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.stop()

    def test_health_and_info(self):
        self.assertEqual(self.client.health(), "SERVING")
        self.assertGreater(self.client.server_info().limits.max_triangles, 0)

    def test_obj_round_trip_within_the_cage(self):
        sent = []
        mesh = self.client.upload_obj("box-obj", SAMPLE, progress=lambda done, total: sent.append((done, total)))
        self.assertEqual(mesh.name, "meshes/box-obj")
        self.assertEqual(sent[-1], (SAMPLE.stat().st_size, SAMPLE.stat().st_size))
        stages = []
        result = self.client.tessellate("box-obj", relative=1e-3, progress=lambda s, f: stages.append((s, f)))
        self.assertTrue(stages, "no progress reported")
        self.assertTrue(all(0.0 <= f <= 1.0 for _, f in stages))
        triangles, low, high, document = glb_triangles_and_box(result.glb)
        self.assertEqual(triangles, result.summary.triangles)
        self.assertLessEqual(result.summary.guaranteed_bound, result.summary.tolerance)
        # A Catmull-Clark limit surface lies inside its control cage's convex hull.
        cage_low, cage_high = cage_box(SAMPLE)
        slack = 1e-5 * float(np.linalg.norm(cage_high - cage_low))
        self.assertTrue(np.all(np.array(low) >= cage_low - slack) and np.all(np.array(high) <= cage_high + slack))
        self.assertIn("tessera", json.dumps(document["asset"]).lower())
        self.assertIn("box-obj", [m.name.split("/")[1] for m in self.client.list_meshes(page_size=1)])

    def test_numpy_arrays_upload_matches_its_canonical_checksum(self):
        positions, sizes, faces, creases = grid_arrays(6)
        mesh = self.client.upload_arrays("grid-numpy", positions, sizes, faces, creases=creases, corners=[(0, 3.0)])
        self.assertEqual(mesh.vertex_count, 49)
        self.assertEqual(mesh.crease_count, 6)
        # The same mesh as plain lists has the same checksum, computed here, not by the server.
        self.assertEqual(mesh.sha256, canonical_sha256(positions.reshape(-1).tolist(), sizes.tolist(),
                                                       faces.reshape(-1).tolist(), creases, [(0, 3.0)]))
        # A large upload goes in several chunks and still matches.
        positions, sizes, faces, _ = grid_arrays(120)
        big = self.client.upload_arrays("grid-big", positions, sizes, faces)
        self.assertEqual(big.face_count, 120 * 120)

    def test_uvs_upload_with_their_rule_and_come_back_as_texcoords(self):
        positions, sizes, faces, _ = grid_arrays(4)
        # One UV per vertex (x/4, y/4), the grid's own parameterization: continuous, no seams.
        uvs = (positions[:, :2] / 4.0).astype(np.float32)
        mesh = self.client.upload_arrays("grid-uv", positions, sizes, faces, uvs=uvs, uv_indices=faces,
                                         uv_interpolation="corners_only")
        self.assertEqual(mesh.options.uv_interpolation, mesh_pb2.UV_INTERPOLATION_LINEAR_CORNERS_ONLY)
        self.assertEqual(mesh.sha256, canonical_sha256(positions.reshape(-1).tolist(), sizes.tolist(),
                                                       faces.reshape(-1).tolist(), uvs=uvs.reshape(-1).tolist(),
                                                       uv_indices=faces.reshape(-1).tolist(),
                                                       uv_interpolation="corners_only"))
        result = self.client.tessellate("grid-uv", relative=1e-3)
        _, _, _, document = glb_triangles_and_box(result.glb)
        attributes = document["meshes"][0]["primitives"][0]["attributes"]
        self.assertIn("TEXCOORD_0", attributes)
        texcoords = document["accessors"][attributes["TEXCOORD_0"]]
        self.assertEqual(texcoords["count"], document["accessors"][attributes["POSITION"]]["count"])

    def test_an_origin_places_the_positions_far_away(self):
        positions, sizes, faces, _ = grid_arrays(4)
        mesh = self.client.upload_arrays("grid-far", positions, sizes, faces, origin=(1e6, -2e6, 0.5))
        # The client checked the stored checksum, origin included; the box is in model units.
        self.assertAlmostEqual(mesh.bounding_box.min.x, 1e6, places=6)
        self.assertAlmostEqual(mesh.bounding_box.max.y, -2e6 + 4, places=6)
        _, _, _, document = glb_triangles_and_box(self.client.tessellate("grid-far", relative=1e-3).glb)
        self.assertEqual(document["nodes"][0]["translation"], [1e6, -2e6, 0.5])

    def test_positions_only_upload_is_the_mesh_a_full_upload_makes(self):
        positions, sizes, faces, creases = grid_arrays(6)
        uvs = (positions[:, :2] / 6.0).astype(np.float32)
        parent = self.client.upload_arrays("grid-parent", positions, sizes, faces, creases=creases, uvs=uvs,
                                           uv_indices=faces)
        edited = positions.copy()
        edited[:, 2] = 0.1 * np.sin(edited[:, 0]) * np.cos(edited[:, 1])
        edit = self.client.upload_positions("grid-edit", topology_of=parent, positions=edited)
        # The checksum of the whole edited mesh, and the one a full upload of it gets.
        full = self.client.upload_arrays("grid-edit-full", edited, sizes, faces, creases=creases, uvs=uvs,
                                         uv_indices=faces)
        self.assertEqual(edit.sha256, full.sha256)
        self.assertEqual(edit.sha256, canonical_sha256(edited.reshape(-1).tolist(), sizes.tolist(),
                                                       faces.reshape(-1).tolist(), creases, uvs=uvs.reshape(-1).tolist(),
                                                       uv_indices=faces.reshape(-1).tolist()))
        self.assertEqual(edit.source_bytes, 4 * edited.size)
        self.assertEqual(edit.crease_count, len(creases))
        # New UVs replace the parent's; a name or an id names the topology's mesh.
        moved = (uvs * 0.5).astype(np.float32)
        again = self.client.upload_positions("meshes/grid-edit2", topology_of="meshes/grid-edit", positions=edited,
                                             uvs=moved)
        self.assertEqual(again.sha256, canonical_sha256(edited.reshape(-1).tolist(), sizes.tolist(),
                                                        faces.reshape(-1).tolist(), creases,
                                                        uvs=moved.reshape(-1).tolist(),
                                                        uv_indices=faces.reshape(-1).tolist()))
        triangles, _, _, _ = glb_triangles_and_box(self.client.tessellate("grid-edit2", relative=1e-3).glb)
        self.assertGreater(triangles, 0)

    def test_positions_only_upload_refusals_name_the_problem(self):
        positions, sizes, faces, _ = grid_arrays(3)
        self.client.upload_arrays("grid-counts", positions, sizes, faces)
        with self.assertRaises(TesseraError) as missing:
            self.client.upload_positions("x-missing", topology_of="no-such-mesh", positions=positions)
        self.assertEqual(missing.exception.code, grpc.StatusCode.NOT_FOUND)
        self.assertIn("meshes/no-such-mesh", missing.exception.message)
        with self.assertRaises(TesseraError) as fewer:
            self.client.upload_positions("x-fewer", topology_of="grid-counts", positions=positions[:-1])
        self.assertEqual(fewer.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
        for part in ("meshes/grid-counts", "45 floats", "16 vertices", "48 floats are needed"):
            self.assertIn(part, fewer.exception.message)
        with self.assertRaises(TesseraError) as uvs:
            self.client.upload_positions("x-uvs", topology_of="grid-counts", positions=positions, uvs=[0.5, 0.5])
        self.assertEqual(uvs.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
        self.assertIn("has no UVs", uvs.exception.message)
        with self.assertRaises(InvalidArgumentError):  # refused here: never sent
            self.client.upload_positions("x-odd", topology_of="never-uploaded", positions=[1.0, 2.0])
        self.assertNotIn("x-missing", [mesh_id(m) for m in self.client.list_meshes()])

    def test_tessellate_to_file_quantized_and_pixel(self):
        self.client.upload_obj("box-file", SAMPLE)
        with tempfile.TemporaryDirectory() as out:
            path = Path(out) / "box.glb"
            summary = self.client.tessellate_to_file("box-file", path, relative=1e-2, encoding="meshopt")
            self.assertEqual(path.stat().st_size, summary.glb_size)
            self.assertEqual(list(Path(out).iterdir()), [path])
        camera = Camera(eye=(0, 0, 6), target=(0, 0, 0), width=640, height=480)
        pixel = self.client.tessellate("box-file", camera=camera, pixel_accuracy=1.0)
        self.assertGreater(pixel.summary.triangles, 0)

    def test_errors_name_the_problem(self):
        with self.assertRaises(TesseraError) as missing:
            self.client.tessellate("no-such-mesh", relative=1e-3)
        self.assertEqual(missing.exception.code, grpc.StatusCode.NOT_FOUND)
        self.client.upload_obj("box-errors", SAMPLE)
        with self.assertRaises(TesseraError) as bad:
            self.client.tessellate("box-errors", relative=2.0)
        self.assertEqual(bad.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
        self.assertIn("relative", bad.exception.message)
        with self.assertRaises(TesseraError) as obj:
            self.client.upload_obj("broken", b"v 0 0 0\nf 1 2 3\n")
        self.assertEqual(obj.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
        self.assertEqual(obj.exception.retries, 0)

    def test_two_tolerances_are_refused_before_anything_is_sent(self):
        # The request's tolerance is a oneof: the second field set would silently win (HTTP refuses
        # the same request with 400). The mesh does not exist: refused here, never asked.
        camera = Camera(eye=(0, 0, 6), target=(0, 0, 0))
        for kwargs in ({"relative": 1e-3, "absolute": 1e-3}, {"relative": 1e-3, "camera": camera},
                       {"absolute": 1e-3, "camera": camera}, {"relative": 1e-3, "pixel_accuracy": 1.0}):
            with self.assertRaises(InvalidArgumentError) as both:
                self.client.tessellate("never-uploaded", **kwargs)
            self.assertEqual(both.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
            self.assertIsInstance(both.exception, ValueError)
        with self.assertRaises(InvalidArgumentError) as named:
            self.client.tessellate("never-uploaded", relative=1e-3, absolute=1e-3)
        self.assertIn("relative and absolute", named.exception.message)
        with self.assertRaises(InvalidArgumentError):
            self.client.render("never-uploaded", [camera], pixel_accuracy=1.0, uniform_level=2)

    def test_names_from_list_meshes_are_accepted_everywhere(self):
        self.client.upload_obj("meshes/box-names", SAMPLE)  # a name works as the id of an upload
        listed = next(m for m in self.client.list_meshes() if m.name == "meshes/box-names")
        self.assertEqual(mesh_id(listed), "box-names")
        for ref in ("box-names", "meshes/box-names", listed):
            self.assertEqual(self.client.get_mesh(ref).name, "meshes/box-names")
            self.assertGreater(self.client.tessellate(ref, relative=1e-2).summary.triangles, 0)
        try:
            frames = self.client.render(listed.name, [Camera(eye=(4, 3, 5), target=(0, 0, 0), width=32, height=32)])
            self.assertEqual(len(frames), 1)
        except TesseraError as error:
            self.assertEqual(error.code, grpc.StatusCode.UNIMPLEMENTED)  # a build that renders nothing
        self.client.delete_mesh(listed.name)
        with self.assertRaises(TesseraError) as gone:
            self.client.get_mesh("box-names")
        self.assertEqual(gone.exception.code, grpc.StatusCode.NOT_FOUND)

    def test_render_frames_match_their_headers(self):
        self.client.upload_obj("box-render", SAMPLE)
        cameras = [Camera(eye=(4, 3, 5), target=(0, 0, 0), width=96, height=64),
                   Camera(eye=(-4, 2, -5), target=(0, 0, 0), width=64, height=48)]
        try:
            frames = self.client.render("box-render", cameras, image_format="raw_rgba")
        except TesseraError as error:
            if error.code == grpc.StatusCode.UNIMPLEMENTED:
                self.skipTest(f"this server build renders nothing: {error.message}")
            raise
        self.assertEqual([f.header.index for f in frames], [0, 1])
        for frame, camera in zip(frames, cameras):
            self.assertEqual(len(frame.image), camera.width * camera.height * 4)
            rgba = np.frombuffer(frame.image, dtype=np.uint8).reshape(camera.height, camera.width, 4)
            self.assertGreater(len(np.unique(rgba.reshape(-1, 4), axis=0)), 1, "a blank frame")


class BusyServerTest(unittest.TestCase):
    """One job slot and no queue: a second job is refused with the server's retry hint."""

    def hold_the_slot(self, blocker: TesseraClient, seconds: float) -> threading.Thread:
        """A job that holds the only slot for `seconds` (the blocking engine runs until the call's
        deadline); returns once the server reports it running."""
        running = threading.Event()
        holder = threading.Thread(target=lambda: self.assertRaises(
            TesseraError, blocker.tessellate, "box", relative=1e-2, timeout=seconds,
            progress=lambda stage, _: running.set() if stage == "test-blocking" else None))
        holder.start()
        self.assertTrue(running.wait(seconds), "the blocking job never ran")
        return holder

    def test_retries_after_the_pushback_then_honours_the_deadline(self):
        server = Server("--test-engine", "block", "--max-concurrent-jobs", "1", "--max-queued-jobs", "0")
        try:
            with TesseraClient(server.address) as blocker, TesseraClient(server.address) as client:
                blocker.upload_obj("box", SAMPLE)
                holder = self.hold_the_slot(blocker, 3.0)
                start = time.monotonic()
                with self.assertRaises(TesseraError) as busy:
                    client.tessellate("box", relative=1e-2, timeout=6.0)
                elapsed = time.monotonic() - start
                holder.join()
                # Refused while the slot was held, sent again after the hint, then admitted once it
                # freed, where the blocking engine keeps it until the whole call's deadline.
                self.assertGreater(busy.exception.retries, 0)
                self.assertEqual(busy.exception.code, grpc.StatusCode.DEADLINE_EXCEEDED)
                self.assertLess(elapsed, 6.0 + 1.0)
                with TesseraClient(server.address, max_retries=0) as no_retry:
                    holder = self.hold_the_slot(blocker, 2.0)
                    with self.assertRaises(TesseraError) as refused:
                        no_retry.tessellate("box", relative=1e-2, timeout=5.0)
                    holder.join()
                self.assertEqual(refused.exception.code, grpc.StatusCode.RESOURCE_EXHAUSTED)
                self.assertEqual(refused.exception.retries, 0)
        finally:
            server.stop()


class IntegrityTest(unittest.TestCase):
    """Checks the client makes on what it receives, against a stand-in server that corrupts its
    stream (the real server's streams are checked the same way in every test above)."""

    def serve(self, glb: bytes, summary_sha: str, summary_size: int):
        from concurrent import futures
        from tessera_client._proto.tessera.v1 import tessellation_pb2, tessellation_pb2_grpc

        class Corrupting(tessellation_pb2_grpc.TessellationServiceServicer):
            def Tessellate(self, request, context):
                yield tessellation_pb2.TessellateResponse(glb_chunk=tessellation_pb2.GlbChunk(offset=0, data=glb))
                yield tessellation_pb2.TessellateResponse(summary=tessellation_pb2.TessellationSummary(
                    glb_size=summary_size, glb_sha256=summary_sha))

        server = grpc.server(futures.ThreadPoolExecutor(max_workers=2))
        tessellation_pb2_grpc.add_TessellationServiceServicer_to_server(Corrupting(), server)
        port = server.add_insecure_port("127.0.0.1:0")
        server.start()
        self.addCleanup(server.stop, None)
        return TesseraClient(f"127.0.0.1:{port}")

    def test_a_glb_that_does_not_match_its_summary_is_refused(self):
        import hashlib
        glb = bytes(range(256)) * 8
        good = self.serve(glb, hashlib.sha256(glb).hexdigest(), len(glb))
        self.assertEqual(good.tessellate("m", relative=1e-2).glb, glb)
        altered = self.serve(glb, hashlib.sha256(glb[:-1] + b"x").hexdigest(), len(glb))
        with self.assertRaises(IntegrityError):
            altered.tessellate("m", relative=1e-2)
        short = self.serve(glb, hashlib.sha256(glb).hexdigest(), len(glb) + 1)
        with self.assertRaises(IntegrityError):
            short.tessellate("m", relative=1e-2)
        good.close(), altered.close(), short.close()


if __name__ == "__main__":
    unittest.main(verbosity=2)
