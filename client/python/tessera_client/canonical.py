"""The server's canonical mesh encoding (proto/tessera/v1/mesh.proto, Mesh.sha256), so that an
arrays upload can be checked against the checksum the server stored."""
import hashlib
import struct
from array import array
from typing import Iterable, Sequence, Tuple

BOUNDARY_EDGE_ONLY = 1  # BOUNDARY_INTERPOLATION_EDGE_ONLY: what an ARRAYS upload gets unspecified
# The UV rule as the encoding's rules word holds it in bits 24-31 (mesh.proto, Mesh.sha256).
UV_RULE_CODES = {"all": 0, "none": 1, "corners_only": 2, "corners_plus1": 3, "corners_plus2": 4, "boundaries": 5}


def _little_endian(values: array) -> bytes:
    if struct.pack("=I", 1) != struct.pack("<I", 1):
        values = array(values.typecode, values)
        values.byteswap()
    return values.tobytes()


def canonical_sha256(positions: Sequence[float], face_sizes: Sequence[int], face_vertices: Sequence[int],
                     creases: Iterable[Tuple[int, int, float]] = (), corners: Iterable[Tuple[int, float]] = (),
                     holes: Sequence[int] = (), boundary: int = BOUNDARY_EDGE_ONLY, uvs: Sequence[float] = (),
                     uv_indices: Sequence[int] = (), uv_interpolation: str = "all",
                     origin: Sequence[float] = (0.0, 0.0, 0.0)) -> str:
    """Lower-case hex SHA-256 of the canonical encoding of these arrays (UVs, u and v per UV with
    one index per face corner, only when given; the point positions are relative to, only when
    not zero)."""
    creases, corners = list(creases), list(corners)
    digest = hashlib.sha256()
    digest.update(b"TSM1" + struct.pack("<I", boundary | UV_RULE_CODES[uv_interpolation] << 24))
    digest.update(struct.pack("<Q", len(positions) // 3) + _little_endian(array("f", positions)))
    digest.update(struct.pack("<Q", len(face_sizes)) + _little_endian(array("i", face_sizes)))
    digest.update(struct.pack("<Q", len(face_vertices)) + _little_endian(array("i", face_vertices)))
    digest.update(struct.pack("<Q", len(creases)))
    for v0, v1, sharpness in creases:
        digest.update(struct.pack("<iif", v0, v1, sharpness))
    digest.update(struct.pack("<Q", len(corners)))
    for vertex, sharpness in corners:
        digest.update(struct.pack("<if", vertex, sharpness))
    digest.update(struct.pack("<Q", len(holes)) + _little_endian(array("i", holes)))
    if len(uv_indices):
        digest.update(b"UVS1" + struct.pack("<Q", len(uvs)) + _little_endian(array("f", uvs)))
        digest.update(struct.pack("<Q", len(uv_indices)) + _little_endian(array("i", uv_indices)))
    if any(origin):
        digest.update(b"ORG1" + struct.pack("<3d", *origin))
    return digest.hexdigest()
