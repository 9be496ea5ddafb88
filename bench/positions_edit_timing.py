#!/usr/bin/env python3
"""The first edits of a model's edit loop, timed from the Python client: a full upload of each
edit (upload_arrays) against a positions-only one (upload_positions), each followed by its first
Tessellate, on a fresh server each way; and the server's topology cache counters after each.

  build/python-client/venv/bin/python bench/positions_edit_timing.py --build build \
      --model ../shared/models/armorguy.obj --relative 1e-3 --edits 3

(the venv is the PythonClient test's, with tessera_client installed)."""
import argparse
import json
import sys
import time
from pathlib import Path

from tessera_client import TesseraClient
from tessera_client._proto.tessera.v1 import mesh_pb2

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "blender"))
from blender_session import metric, start_server  # noqa: E402 (tessera-server on loopback; no Blender needed)


def loop(build, model, relative, edits, positions_only):
    server, address, metrics_address = start_server(str(build / "server/tessera-server"))
    try:
        rows = []
        with TesseraClient(address) as client:
            client.upload_obj("parent", model)
            parent = mesh_pb2.MeshArrays()
            for message in client._meshes.DownloadMesh(mesh_pb2.DownloadMeshRequest(name="meshes/parent")):
                if message.HasField("arrays"):
                    parent.MergeFrom(message.arrays)
            start = time.perf_counter()
            client.tessellate("parent", relative=relative)
            rows.append({"step": "parent", "upload_s": None, "tessellate_s": round(time.perf_counter() - start, 3)})
            positions = list(parent.positions)
            for edit in range(1, edits + 1):
                moved = [p * (1 + 0.01 * edit) if i % 3 == 1 else p for i, p in enumerate(positions)]
                start = time.perf_counter()
                if positions_only:
                    client.upload_positions(f"edit{edit}", topology_of="parent", positions=moved)
                else:
                    client.upload_arrays(f"edit{edit}", moved, list(parent.face_sizes), list(parent.face_vertices),
                                         creases=[(c.v0, c.v1, c.sharpness) for c in parent.creases],
                                         corners=[(c.vertex, c.sharpness) for c in parent.corners],
                                         holes=list(parent.holes), uvs=list(parent.uvs),
                                         uv_indices=list(parent.uv_indices))
                uploaded = time.perf_counter()
                client.tessellate(f"edit{edit}", relative=relative)
                done = time.perf_counter()
                rows.append({"step": f"edit {edit}", "upload_s": round(uploaded - start, 3),
                             "tessellate_s": round(done - uploaded, 3),
                             "topology_hits": int(metric(metrics_address, "tessera_topology_cache_hits_total")),
                             "topology_built": int(metric(metrics_address, "tessera_topology_cache_misses_total"))})
        return rows
    finally:
        server.terminate()
        server.wait(timeout=30)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default="build")
    parser.add_argument("--model", default="../shared/models/armorguy.obj")
    parser.add_argument("--relative", type=float, default=1e-3)
    parser.add_argument("--edits", type=int, default=3)
    args = parser.parse_args()
    build, model = Path(args.build).resolve(), Path(args.model).resolve()
    result = {"model": model.name, "relative": args.relative}
    for name, positions_only in (("full_uploads", False), ("positions_only", True)):
        result[name] = loop(build, model, args.relative, args.edits, positions_only)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
