"""The Blender add-on's GLB reader (client/blender/tessera_subdiv/glb_mesh.py) and its meshopt
decoder (meshopt_decode.py) outside Blender: they need only NumPy. The references are independent
of the decoder: the extension specification's own worked example, and the quantized GLB of the
same request, which the meshopt file compresses (docs/GLB.md: the same triangles over the same
vertices, reordered), written by the tessera CLI.
Usage: glb_reader_test.py TESSERA_CLI MODELS_DIR"""
import subprocess
import sys
import tempfile
import types
import unittest
from pathlib import Path

import numpy as np

ADDON = Path(__file__).resolve().parents[2] / "client" / "blender" / "tessera_subdiv"
# The add-on's package imports bpy; its GLB modules do not, so they are loaded as a bare package.
_package = types.ModuleType("tessera_subdiv")
_package.__path__ = [str(ADDON)]
sys.modules["tessera_subdiv"] = _package
from tessera_subdiv import meshopt_decode  # noqa: E402
from tessera_subdiv.glb_mesh import read_glb  # noqa: E402

CLI, MODELS = sys.argv[1], Path(sys.argv[2])


def tessellate(obj: Path, encoding: str, out: Path) -> bytes:
    path = out / f"{obj.stem}-{encoding}.glb"
    subprocess.run([CLI, "tessellate", str(obj), "--tolerance", "1e-3", "--relative", "--encoding", encoding,
                    "-o", str(path)], check=True, stdout=subprocess.DEVNULL)
    return path.read_bytes()


def compressed_views(glb: bytes) -> list:
    """The EXT_meshopt_compression objects of a GLB's views, each with its compressed bytes."""
    import json
    import struct
    json_length = struct.unpack_from("<I", glb, 12)[0]
    document, bin_at = json.loads(glb[20:20 + json_length]), 20 + json_length + 8
    views = [v["extensions"]["EXT_meshopt_compression"] for v in document["bufferViews"] if "extensions" in v]
    for view in views:
        start = bin_at + view.get("byteOffset", 0)
        view["data"] = glb[start:start + view["byteLength"]]
    return views


def triangles(data: dict) -> list:
    """Each triangle as its corners' (position, UV), rotated to start at the smallest: the same
    triangles in any vertex and triangle order compare equal."""
    uvs = data["uvs"] if data["uvs"] is not None else np.zeros((len(data["positions"]), 2))
    corners = [tuple(p) + tuple(t) for p, t in zip(data["positions"].tolist(), uvs.tolist())]
    out = []
    for a, b, c in data["indices"].reshape(-1, 3).tolist():
        tri = (corners[a], corners[b], corners[c])
        first = tri.index(min(tri))
        out.append(tri[first:] + tri[:first])
    return sorted(out)


class MeshoptDecoderTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scratch = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.scratch.cleanup()

    def test_the_specifications_four_bit_example(self):
        # Appendix A, mode 0: ten bytes in 4-bit sentinel coding and the deltas they decode to.
        stream = bytes([0x17, 0x5F, 0xF0, 0xBC, 0x77, 0xA9, 0x21, 0x00, 0x34, 0xB5])
        deltas = meshopt_decode._group_deltas(meshopt_decode._Reader(stream, 0, len(stream)), 2)
        signed = np.frombuffer(deltas.translate(meshopt_decode._UNZIGZAG), dtype=np.int8).tolist()
        self.assertEqual(signed, [-1, -4, -3, 26, -91, 0, -6, 6, -4, -4, 5, -5, 1, -1, 0, 0])

    def check_same_as_quantized(self, obj: Path):
        out = Path(self.scratch.name)
        quantized, meshopt = tessellate(obj, "quantized", out), tessellate(obj, "meshopt", out)
        self.assertIn(b"EXT_meshopt_compression", meshopt)
        a, b = read_glb(quantized), read_glb(meshopt)
        self.assertEqual(len(a["positions"]), len(b["positions"]))
        expected, decoded = triangles(a), triangles(b)
        # Not assertEqual: its diff of two long lists takes minutes.
        differ = sum(x != y for x, y in zip(expected, decoded))
        self.assertTrue(expected == decoded, f"{differ} of {len(expected)} triangles differ")
        return a, b, len(meshopt)

    def test_meshopt_decodes_to_the_quantized_files_triangles(self):
        _, data, size = self.check_same_as_quantized(MODELS / "bigguy.obj")
        self.assertGreater(len(data["indices"]) // 3, 10000)
        # Positions scaled back by the node's grid: inside the cage's box (bigguy's, about 20 units).
        self.assertTrue(np.all(np.abs(data["positions"]) < 12.0))
        self.assertTrue(np.allclose(np.linalg.norm(data["normals"], axis=1), 1.0))

    def test_uvs_survive_meshopt(self):
        a, b, _ = self.check_same_as_quantized(MODELS / "opensubdiv-shapes" / "catmark_bishop.obj")
        self.assertIsNotNone(b["uvs"])

    def test_a_damaged_stream_is_refused(self):
        glb = tessellate(MODELS / "bigguy.obj", "meshopt", Path(self.scratch.name))
        with self.assertRaises(ValueError):
            meshopt_decode.decode_attributes(b"\xa1" + bytes(64), 4, 8)  # a later codec version
        with self.assertRaises(ValueError):
            meshopt_decode.decode_triangles(b"\xe1\x00\x00" + bytes(16), 9, 4)  # too few codes
        with self.assertRaises(ValueError):
            meshopt_decode.decode_view(bytes(64), 4, 4, "ATTRIBUTES", "OCTAHEDRAL")
        # The file's own streams with ten bytes cut from their middle: refused, not read as other geometry.
        for view in compressed_views(glb):
            damaged = view["data"][:len(view["data"]) // 2] + view["data"][len(view["data"]) // 2 + 10:]
            with self.assertRaises(ValueError, msg=view["mode"]):
                meshopt_decode.decode_view(damaged, view["count"], view["byteStride"], view["mode"])


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
