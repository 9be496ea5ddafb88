#!/usr/bin/env python3
"""Bytes on the wire for an edit of a model: a full upload against a positions-only one
(mesh.proto, UploadMeshHeader.topology_of), through the `tessera` CLI and the Python client.

Every call goes through a TCP relay on loopback that counts the bytes each way (the TCP payload:
gRPC's HTTP/2 frames, headers and all). The edit moves every vertex (y scaled by 1.02), which a
positions-only upload sends whole anyway.

  python3 bench/upload_bytes.py --build build --model ../shared/models/armorguy.obj [--python VENV_PYTHON]

--python runs the Python client part with that interpreter (a venv with tessera_client, e.g. the
PythonClient test's build/python-client/venv/bin/python)."""
import argparse
import json
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "blender"))
from blender_session import start_server  # noqa: E402 (tessera-server on loopback; no Blender needed)


class Relay:
    """Listens on a free loopback port and relays every connection to `target`, counting bytes."""

    def __init__(self, target: str):
        host, port = target.rsplit(":", 1)
        self.target = (host, int(port))
        self.listener = socket.socket()
        self.listener.bind(("127.0.0.1", 0))
        self.listener.listen(16)
        self.address = f"127.0.0.1:{self.listener.getsockname()[1]}"
        self.up = 0    # client -> server
        self.down = 0  # server -> client
        self.lock = threading.Lock()
        threading.Thread(target=self._accept, daemon=True).start()

    def reset(self):
        with self.lock:
            counts = (self.up, self.down)
            self.up = self.down = 0
        return counts

    def _accept(self):
        while True:
            client, _ = self.listener.accept()
            server = socket.create_connection(self.target)
            for a, b, up in ((client, server, True), (server, client, False)):
                threading.Thread(target=self._pump, args=(a, b, up), daemon=True).start()

    def _pump(self, source, sink, up):
        try:
            while True:
                data = source.recv(1 << 16)
                if not data:
                    break
                with self.lock:
                    if up:
                        self.up += len(data)
                    else:
                        self.down += len(data)
                sink.sendall(data)
        except OSError:
            pass
        finally:
            try:
                sink.shutdown(socket.SHUT_WR)
            except OSError:
                pass


def edited_obj(text: str) -> str:
    out = []
    for line in text.splitlines():
        if line.startswith("v "):
            x, y, z = (float(v) for v in line.split()[1:4])
            line = f"v {x!r} {y * 1.02 + 0.01!r} {z!r}"
        out.append(line)
    return "\n".join(out) + "\n"


PYTHON_PART = r"""
import json, sys
from tessera_client import TesseraClient
from tessera_client._proto.tessera.v1 import mesh_pb2
address, edit_obj = sys.argv[1], sys.argv[2]
with TesseraClient(address) as client:
    mesh = client.get_mesh("py-parent")
    # The parent's arrays (read with the server's DownloadMesh, before the counters are reset), as a
    # modelling tool holds its cage; the edit's positions from the edited OBJ (no origin).
    parent = mesh_pb2.MeshArrays()
    for message in client._meshes.DownloadMesh(mesh_pb2.DownloadMeshRequest(name=mesh.name)):
        if message.HasField("arrays"):
            parent.MergeFrom(message.arrays)
    positions = [float(v) for line in open(edit_obj) if line.startswith("v ") for v in line.split()[1:4]]
    print(json.dumps({"vertices": len(positions) // 3}), flush=True)
    input()  # the relay's counters are reset here: a full upload of the edit
    full = client.upload_arrays("py-edit-full", positions, list(parent.face_sizes), list(parent.face_vertices),
                                creases=[(c.v0, c.v1, c.sharpness) for c in parent.creases],
                                corners=[(c.vertex, c.sharpness) for c in parent.corners], holes=list(parent.holes),
                                uvs=list(parent.uvs), uv_indices=list(parent.uv_indices))
    print(json.dumps({"sha256": full.sha256, "source_bytes": full.source_bytes}), flush=True)
    input()  # and again: the same edit, positions only
    edit = client.upload_positions("py-edit", topology_of=mesh, positions=positions)
    print(json.dumps({"sha256": edit.sha256, "source_bytes": edit.source_bytes}), flush=True)
"""


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default="build")
    parser.add_argument("--model", default="../shared/models/armorguy.obj")
    parser.add_argument("--python", help="a Python with tessera_client installed")
    args = parser.parse_args()
    build, model = Path(args.build).resolve(), Path(args.model).resolve()
    work = Path(tempfile.mkdtemp(prefix="upload-bytes-"))
    server, address, _ = start_server(str(build / "server/tessera-server"))
    try:
        relay = Relay(address)
        edit = work / (model.stem + "-edit.obj")
        edit.write_text(edited_obj(model.read_text()))
        cli = str(build / "client/tessera")

        def run(*command):
            relay.reset()
            start = time.perf_counter()
            output = subprocess.run([cli, "--server", relay.address, *command], check=True, capture_output=True,
                                    text=True).stdout
            seconds = time.perf_counter() - start
            time.sleep(0.2)  # the relay's last reads
            up, down = relay.reset()
            sha = next(l.split()[1] for l in output.splitlines() if l.startswith("sha256"))
            return {"up": up, "down": down, "seconds": round(seconds, 3), "sha256": sha}

        results = {"model": model.name, "obj_bytes": model.stat().st_size, "edit_obj_bytes": edit.stat().st_size}
        results["parent_obj"] = run("upload", str(model), "--name", "parent")
        results["edit_full_obj"] = run("upload", str(edit), "--name", "edit-full")
        results["edit_positions_cli"] = run("upload", str(edit), "--name", "edit-pos", "--topology-of", "meshes/parent")
        if args.python:
            # The parent as arrays, for the Python client's full upload of the edit (upload_arrays).
            code = PYTHON_PART
            subprocess.run([cli, "--server", address, "upload", str(model), "--name", "py-parent"], check=True,
                           capture_output=True)
            child = subprocess.Popen([args.python, "-c", code, relay.address, str(edit)], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, text=True)
            json.loads(child.stdout.readline())
            for key in ("edit_full_arrays_python", "edit_positions_python"):
                time.sleep(0.2)
                relay.reset()
                start = time.perf_counter()
                child.stdin.write("\n")
                child.stdin.flush()
                done = json.loads(child.stdout.readline())
                seconds = time.perf_counter() - start
                time.sleep(0.2)
                up, down = relay.reset()
                results[key] = {"up": up, "down": down, "seconds": round(seconds, 3), **done}
            child.wait()
        full = results["edit_full_obj"]["up"]
        for key in ("edit_positions_cli", "edit_positions_python"):
            if key in results:
                results[key]["share_of_full_obj_upload"] = round(results[key]["up"] / full, 4)
        if "edit_full_arrays_python" in results:
            results["edit_positions_python"]["share_of_full_arrays_upload"] = round(
                results["edit_positions_python"]["up"] / results["edit_full_arrays_python"]["up"], 4)
        results["same_sha256"] = len({results[key]["sha256"] for key in results
                                      if key.startswith("edit_") and isinstance(results[key], dict)}) == 1
        print(json.dumps(results, indent=2))
    finally:
        server.terminate()
        server.wait(timeout=30)


if __name__ == "__main__":
    main()
