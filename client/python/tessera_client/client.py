"""A client for tessera-server's gRPC API (proto/tessera/v1): upload control meshes, tessellate
them to GLB within a tolerance of the limit surface, render frames, ask for health.

Every call takes a deadline (`timeout`, seconds, for the whole call including retries). A call the
server refuses as busy (RESOURCE_EXHAUSTED with the trailing metadata "grpc-retry-pushback-ms") is
sent again after the time the server asks for, while the deadline allows; any other error raises
TesseraError with the server's status code and message."""
import hashlib
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Iterator, List, Optional, Sequence, Tuple, Union

import grpc

from tessera_client._proto.grpc.health.v1 import health_pb2, health_pb2_grpc
from tessera_client._proto.tessera.v1 import (geometry_pb2, mesh_pb2, mesh_pb2_grpc, render_pb2, render_pb2_grpc,
                                              server_info_pb2, server_info_pb2_grpc, tessellation_pb2,
                                              tessellation_pb2_grpc)
from tessera_client.canonical import BOUNDARY_EDGE_ONLY, canonical_sha256

CHUNK_BYTES = 64 * 1024
# Array values per upload message: 16K floats or ints is 64 KiB of payload.
CHUNK_VALUES = 16 * 1024
PUSHBACK_KEY = "grpc-retry-pushback-ms"
_SERVICE_CONFIG = (Path(__file__).resolve().parent / "_proto" / "service_config.json").read_text()

ProgressCallback = Callable[[str, float], None]

_BOUNDARY = {
    None: mesh_pb2.BOUNDARY_INTERPOLATION_UNSPECIFIED,
    "edge_only": mesh_pb2.BOUNDARY_INTERPOLATION_EDGE_ONLY,
    "edge_and_corner": mesh_pb2.BOUNDARY_INTERPOLATION_EDGE_AND_CORNER,
}
# Sdc's FVarLinearInterpolation by name (mesh.proto UvInterpolation).
_UV_INTERPOLATION = {
    "all": mesh_pb2.UV_INTERPOLATION_LINEAR_ALL,
    "none": mesh_pb2.UV_INTERPOLATION_LINEAR_NONE,
    "corners_only": mesh_pb2.UV_INTERPOLATION_LINEAR_CORNERS_ONLY,
    "corners_plus1": mesh_pb2.UV_INTERPOLATION_LINEAR_CORNERS_PLUS1,
    "corners_plus2": mesh_pb2.UV_INTERPOLATION_LINEAR_CORNERS_PLUS2,
    "boundaries": mesh_pb2.UV_INTERPOLATION_LINEAR_BOUNDARIES,
}
_ENCODING = {
    "float": tessellation_pb2.GLB_ENCODING_FLOAT,
    "quantized": tessellation_pb2.GLB_ENCODING_QUANTIZED,
    "meshopt": tessellation_pb2.GLB_ENCODING_MESHOPT,
}
_IMAGE_FORMAT = {
    "png": render_pb2.IMAGE_FORMAT_PNG,
    "jpeg": render_pb2.IMAGE_FORMAT_JPEG,
    "exr": render_pb2.IMAGE_FORMAT_EXR,
    "raw_rgba": render_pb2.IMAGE_FORMAT_RAW_RGBA,
}


class TesseraError(Exception):
    """A call that failed: the gRPC status code and the server's message (which names the field, or
    the OBJ source and line, at fault)."""

    def __init__(self, code: grpc.StatusCode, message: str, retries: int = 0):
        super().__init__(f"{code.name}: {message}")
        self.code = code
        self.message = message
        self.retries = retries


class InvalidArgumentError(TesseraError, ValueError):
    """Arguments the client refuses before sending anything (the server would refuse them too, or
    silently pick one): INVALID_ARGUMENT, and a ValueError for code that catches those."""

    def __init__(self, message: str):
        super().__init__(grpc.StatusCode.INVALID_ARGUMENT, message)


class IntegrityError(TesseraError):
    """Bytes that do not match the checksum the server sent (or, for an arrays upload, the
    checksum of what was sent does not match the one the server stored)."""

    def __init__(self, message: str):
        super().__init__(grpc.StatusCode.DATA_LOSS, message)


@dataclass
class Camera:
    eye: Tuple[float, float, float]
    target: Tuple[float, float, float]
    up: Tuple[float, float, float] = (0.0, 1.0, 0.0)
    fov_y_deg: float = 45.0
    width: int = 1280
    height: int = 720

    def to_proto(self) -> tessellation_pb2.Camera:
        vec = lambda v: geometry_pb2.Vec3(x=v[0], y=v[1], z=v[2])  # noqa: E731
        return tessellation_pb2.Camera(eye=vec(self.eye), target=vec(self.target), up=vec(self.up),
                                       fov_y_deg=self.fov_y_deg, width=self.width, height=self.height)


@dataclass
class Tessellation:
    glb: bytes
    summary: tessellation_pb2.TessellationSummary


@dataclass
class Frame:
    header: render_pb2.FrameHeader
    image: bytes


def _pushback_seconds(error: grpc.RpcError) -> Optional[float]:
    """The server's retry hint on a busy refusal, in seconds (None: not a busy refusal)."""
    if error.code() != grpc.StatusCode.RESOURCE_EXHAUSTED:
        return None
    for key, value in error.trailing_metadata() or ():
        if key == PUSHBACK_KEY:
            try:
                return max(0.0, int(value) / 1000.0)
            except ValueError:
                return None
    return None


def _append_chunk(buffer: bytearray, offset: int, data: bytes, what: str) -> None:
    """A streamed chunk, which must start where the bytes so far end."""
    if offset != len(buffer):
        raise IntegrityError(f"{what}: chunk at offset {offset}, expected {len(buffer)}")
    buffer += data


def _check_received(data: bytearray, size: int, sha256: str, what: str) -> bytes:
    """The bytes of a stream, if they have the size and SHA-256 the server announced."""
    if len(data) != size or hashlib.sha256(data).hexdigest() != sha256:
        raise IntegrityError(f"{what}: {len(data)} bytes received do not match the announced "
                             f"size {size} and sha256 {sha256}")
    return bytes(data)


MESH_NAME_PREFIX = "meshes/"
MeshRef = Union[str, mesh_pb2.Mesh]


def mesh_id(mesh: MeshRef) -> str:
    """The id of a mesh given as its id ("box"), its resource name ("meshes/box", as list_meshes()
    and the server's messages name it) or a Mesh message."""
    name = mesh.name if isinstance(mesh, mesh_pb2.Mesh) else str(mesh)
    return name[len(MESH_NAME_PREFIX):] if name.startswith(MESH_NAME_PREFIX) else name


def _mesh_name(mesh: MeshRef) -> str:
    return MESH_NAME_PREFIX + mesh_id(mesh)


def _at_most_one(what: str, **given) -> None:
    """The request's fields form a oneof: a second one set would silently replace the first."""
    named = [name for name, value in given.items() if value is not None]
    if len(named) > 1:
        raise InvalidArgumentError(f"{what}: give one of {', '.join(given)}, not several (got {' and '.join(named)})")


def _flat(values, kind) -> list:
    """A flat list from a sequence or a NumPy array (any shape)."""
    if hasattr(values, "tolist"):
        values = values.reshape(-1).tolist() if hasattr(values, "reshape") else values.tolist()
    return [kind(v) for v in values]


class TesseraClient:
    """A connection to one tessera-server.

    >>> with TesseraClient("127.0.0.1:50051") as client:
    ...     mesh = client.upload_obj("bigguy", "bigguy.obj")
    ...     result = client.tessellate("bigguy", relative=1e-3)
    ...     Path("bigguy.glb").write_bytes(result.glb)
    """

    def __init__(self, target: str, token: Optional[str] = None, root_certificates: Optional[bytes] = None,
                 max_retries: int = 8, options: Sequence[Tuple[str, object]] = ()):
        """`target` is HOST:PORT, or any gRPC target naming several servers (dns:///NAME:PORT,
        ipv4:A:P,B:P), balanced round-robin over those that pass health checks, with calls refused
        as UNAVAILABLE retried transparently (the API's service config,
        proto/tessera/v1/service_config.json; an `options` entry "grpc.service_config" replaces it);
        `token` the server's bearer token, if it asks for one; `root_certificates` (PEM) makes the
        channel TLS; `max_retries` bounds how many times a call refused as busy is sent again
        (within its deadline)."""
        if not any(name == "grpc.service_config" for name, _ in options):
            options = [*options, ("grpc.service_config", _SERVICE_CONFIG)]
        if root_certificates is not None:
            self._channel = grpc.secure_channel(target, grpc.ssl_channel_credentials(root_certificates), options)
        else:
            self._channel = grpc.insecure_channel(target, options)
        self._metadata = (("authorization", f"Bearer {token}"),) if token else ()
        self.max_retries = max_retries
        self.retries = 0  # busy refusals retried over this client's life
        self._meshes = mesh_pb2_grpc.MeshServiceStub(self._channel)
        self._tessellation = tessellation_pb2_grpc.TessellationServiceStub(self._channel)
        self._render = render_pb2_grpc.RenderServiceStub(self._channel)
        self._info = server_info_pb2_grpc.ServerInfoServiceStub(self._channel)
        self._health = health_pb2_grpc.HealthStub(self._channel)

    def close(self) -> None:
        self._channel.close()

    def __enter__(self) -> "TesseraClient":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # The retry loop every call goes through: `attempt(timeout)` makes one attempt, `timeout` the
    # seconds left of the whole call (None: no deadline).
    def _call(self, attempt, timeout: Optional[float]):
        deadline = None if timeout is None else time.monotonic() + timeout
        retries = 0
        while True:
            remaining = None if deadline is None else deadline - time.monotonic()
            if remaining is not None and remaining <= 0:
                raise TesseraError(grpc.StatusCode.DEADLINE_EXCEEDED, "deadline passed while waiting to retry", retries)
            try:
                return attempt(remaining)
            except grpc.RpcError as error:
                wait = _pushback_seconds(error)
                remaining = None if deadline is None else deadline - time.monotonic()
                if wait is None or retries >= self.max_retries or (remaining is not None and wait >= remaining):
                    raise TesseraError(error.code(), error.details() or "", retries) from None
                retries += 1
                self.retries += 1
                time.sleep(wait)

    def _unary(self, method, request, timeout: Optional[float]):
        return self._call(lambda t: method(request, timeout=t, metadata=self._metadata), timeout)

    # -- meshes ---------------------------------------------------------------------------------

    def upload_obj(self, mesh: str, obj: Union[str, Path, bytes], display_name: Optional[str] = None,
                   boundary: Optional[str] = None, progress: Optional[Callable[[int, int], None]] = None,
                   timeout: Optional[float] = None) -> mesh_pb2.Mesh:
        """Uploads a Wavefront OBJ (a path, or its bytes) as `mesh` (an id, or "meshes/ID") with OpenSubdiv's "t" tags; `boundary` is
        None (the file's tag), "edge_only" or "edge_and_corner". `progress(sent, total)` after each
        chunk."""
        if isinstance(obj, (str, Path)):
            data = Path(obj).read_bytes()
            display_name = display_name or Path(obj).name
        else:
            data = bytes(obj)
        header = mesh_pb2.UploadMeshHeader(mesh_id=mesh_id(mesh), display_name=display_name or "",
                                           format=mesh_pb2.MESH_FORMAT_OBJ, total_bytes=len(data),
                                           options=mesh_pb2.SubdivisionOptions(
                                               boundary_interpolation=_BOUNDARY[boundary]))

        def messages() -> Iterator[mesh_pb2.UploadMeshRequest]:
            yield mesh_pb2.UploadMeshRequest(header=header)
            for offset in range(0, len(data), CHUNK_BYTES):
                yield mesh_pb2.UploadMeshRequest(obj_data=data[offset:offset + CHUNK_BYTES])
                if progress:
                    progress(min(offset + CHUNK_BYTES, len(data)), len(data))

        return self._call(lambda t: self._meshes.UploadMesh(messages(), timeout=t, metadata=self._metadata), timeout)

    def upload_arrays(self, mesh: str, positions, face_sizes, face_vertices,
                      creases: Iterable[Tuple[int, int, float]] = (), corners: Iterable[Tuple[int, float]] = (),
                      holes: Sequence[int] = (), display_name: Optional[str] = None, boundary: Optional[str] = None,
                      uvs=(), uv_indices=(), uv_interpolation: str = "all", origin=(0.0, 0.0, 0.0),
                      timeout: Optional[float] = None) -> mesh_pb2.Mesh:
        """Uploads a mesh as arrays (lists or NumPy arrays) as `mesh` (an id, or "meshes/ID"): positions x, y, z per vertex (any shape
        that flattens to that), face sizes, face vertices counter-clockwise, creases (v0, v1,
        sharpness), corners (vertex, sharpness), hole faces, and optionally UVs (u, v per UV) with
        the UV of every face corner and OpenSubdiv's rule for them ("all", "none", "corners_only",
        "corners_plus1", "corners_plus2", "boundaries"); `origin`, the point the positions are
        relative to (a mesh far from the origin keeps its detail in float positions). Checks the
        server's stored checksum against the one of what was sent."""
        positions = _flat(positions, float)
        face_sizes, face_vertices = _flat(face_sizes, int), _flat(face_vertices, int)
        creases = [(int(a), int(b), float(s)) for a, b, s in creases]
        corners = [(int(v), float(s)) for v, s in corners]
        holes = _flat(holes, int)
        uvs, uv_indices = _flat(uvs, float), _flat(uv_indices, int)
        origin = tuple(float(c) for c in origin)
        total = 4 * (len(positions) + len(face_sizes) + len(face_vertices) + len(holes) + len(uvs) + len(uv_indices)) \
            + 12 * len(creases) + 8 * len(corners) + (24 if any(origin) else 0)
        header = mesh_pb2.UploadMeshHeader(mesh_id=mesh_id(mesh), display_name=display_name or "",
                                           format=mesh_pb2.MESH_FORMAT_ARRAYS, total_bytes=total,
                                           options=mesh_pb2.SubdivisionOptions(
                                               boundary_interpolation=_BOUNDARY[boundary],
                                               uv_interpolation=_UV_INTERPOLATION[uv_interpolation]))

        def messages() -> Iterator[mesh_pb2.UploadMeshRequest]:
            yield mesh_pb2.UploadMeshRequest(header=header)
            for name, values in (("positions", positions), ("face_sizes", face_sizes),
                                 ("face_vertices", face_vertices), ("holes", holes), ("uvs", uvs),
                                 ("uv_indices", uv_indices)):
                for offset in range(0, len(values), CHUNK_VALUES):
                    arrays = mesh_pb2.MeshArrays()
                    getattr(arrays, name).extend(values[offset:offset + CHUNK_VALUES])
                    yield mesh_pb2.UploadMeshRequest(arrays=arrays)
            for offset in range(0, len(creases), CHUNK_VALUES // 3):
                arrays = mesh_pb2.MeshArrays(creases=[mesh_pb2.Crease(v0=a, v1=b, sharpness=s)
                                                      for a, b, s in creases[offset:offset + CHUNK_VALUES // 3]])
                yield mesh_pb2.UploadMeshRequest(arrays=arrays)
            if any(origin):
                yield mesh_pb2.UploadMeshRequest(arrays=mesh_pb2.MeshArrays(
                    origin=geometry_pb2.Vec3(x=origin[0], y=origin[1], z=origin[2])))
            for offset in range(0, len(corners), CHUNK_VALUES // 2):
                arrays = mesh_pb2.MeshArrays(corners=[mesh_pb2.Corner(vertex=v, sharpness=s)
                                                      for v, s in corners[offset:offset + CHUNK_VALUES // 2]])
                yield mesh_pb2.UploadMeshRequest(arrays=arrays)

        mesh = self._call(lambda t: self._meshes.UploadMesh(messages(), timeout=t, metadata=self._metadata), timeout)
        boundary_value = _BOUNDARY[boundary] or BOUNDARY_EDGE_ONLY
        expected = canonical_sha256(positions, face_sizes, face_vertices, creases, corners, holes, boundary_value,
                                    uvs, uv_indices, uv_interpolation, origin)
        if mesh.sha256 != expected:
            raise IntegrityError(f"the server stored {mesh.name} with sha256 {mesh.sha256}, "
                                 f"but what was sent has {expected}")
        return mesh

    def upload_positions(self, mesh: str, topology_of: MeshRef, positions, uvs=None, origin=(0.0, 0.0, 0.0),
                         display_name: Optional[str] = None, timeout: Optional[float] = None) -> mesh_pb2.Mesh:
        """Uploads an edit of a stored mesh as `mesh` (an id, or "meshes/ID"), sending only what
        changed: the mesh takes the faces, creases, corners, holes, rules and UV indices of
        `topology_of` (an id, a name or a Mesh), with these positions (x, y, z for every one of its
        vertices; lists or NumPy arrays), `uvs` (u, v for every one of its UVs) or its UVs when
        None, and `origin` (as upload_arrays: not taken from `topology_of`). The result is a whole
        mesh with its own id and checksum, the one upload_arrays of the same arrays would store;
        the server keeps the shared topology ready, so the edit's first tessellation only refines
        its positions. A count that differs from `topology_of`'s raises TesseraError with
        INVALID_ARGUMENT (the message names the mesh and both counts), a `topology_of` that does
        not exist NOT_FOUND; positions or UVs that are not whole triples or pairs raise
        InvalidArgumentError before anything is sent."""
        positions = _flat(positions, float)
        uvs = _flat(uvs, float) if uvs is not None else []
        origin = tuple(float(c) for c in origin)
        if len(positions) % 3:
            raise InvalidArgumentError(f"upload_positions: {len(positions)} position values are not whole x, y, z triples")
        if uvs and len(uvs) % 2:
            raise InvalidArgumentError(f"upload_positions: {len(uvs)} UV values are not whole u, v pairs")
        total = 4 * (len(positions) + len(uvs)) + (24 if any(origin) else 0)
        header = mesh_pb2.UploadMeshHeader(mesh_id=mesh_id(mesh), display_name=display_name or "",
                                           format=mesh_pb2.MESH_FORMAT_ARRAYS, total_bytes=total,
                                           topology_of=_mesh_name(topology_of))

        def messages() -> Iterator[mesh_pb2.UploadMeshRequest]:
            yield mesh_pb2.UploadMeshRequest(header=header)
            for name, values in (("positions", positions), ("uvs", uvs)):
                for offset in range(0, len(values), CHUNK_VALUES):
                    arrays = mesh_pb2.MeshArrays()
                    getattr(arrays, name).extend(values[offset:offset + CHUNK_VALUES])
                    yield mesh_pb2.UploadMeshRequest(arrays=arrays)
            if any(origin):
                yield mesh_pb2.UploadMeshRequest(arrays=mesh_pb2.MeshArrays(
                    origin=geometry_pb2.Vec3(x=origin[0], y=origin[1], z=origin[2])))

        stored = self._call(lambda t: self._meshes.UploadMesh(messages(), timeout=t, metadata=self._metadata), timeout)
        if stored.vertex_count != len(positions) // 3:
            raise IntegrityError(f"the server stored {stored.name} with {stored.vertex_count} vertices, "
                                 f"but {len(positions) // 3} were sent")
        return stored

    def get_mesh(self, mesh: MeshRef, timeout: Optional[float] = None) -> mesh_pb2.Mesh:
        request = mesh_pb2.GetMeshRequest(name=_mesh_name(mesh))
        return self._unary(self._meshes.GetMesh, request, timeout)

    def list_meshes(self, page_size: int = 0, timeout: Optional[float] = None) -> List[mesh_pb2.Mesh]:
        """Every stored mesh, in id order (all pages)."""
        meshes, token = [], ""
        while True:
            request = mesh_pb2.ListMeshesRequest(page_size=page_size, page_token=token)
            page = self._unary(self._meshes.ListMeshes, request, timeout)
            meshes.extend(page.meshes)
            token = page.next_page_token
            if not token:
                return meshes

    def delete_mesh(self, mesh: MeshRef, timeout: Optional[float] = None) -> None:
        request = mesh_pb2.DeleteMeshRequest(name=_mesh_name(mesh))
        self._unary(self._meshes.DeleteMesh, request, timeout)

    # -- tessellation ---------------------------------------------------------------------------

    def tessellate(self, mesh: MeshRef, relative: Optional[float] = None, absolute: Optional[float] = None,
                   camera: Optional[Camera] = None, pixel_accuracy: Optional[float] = None,
                   eta: Optional[float] = None, uniform_level: Optional[int] = None,
                   max_triangles: Optional[int] = None, encoding: str = "float",
                   progress: Optional[ProgressCallback] = None, timeout: Optional[float] = None) -> Tessellation:
        """A GLB within a tolerance of the mesh's limit surface: `relative` (a fraction of the
        bounding-box diagonal), `absolute` (model units), or `camera` (pixel accuracy on its screen,
        `pixel_accuracy` pixels, default 0.5); or `uniform_level`. `encoding`: "float",
        "quantized" or "meshopt". `progress(stage, fraction)` as the server reports it. The GLB is
        checked against the summary's size and sha256. `mesh` is an id, a name ("meshes/ID") or a
        Mesh. Giving more than one of relative, absolute and camera raises InvalidArgumentError, as
        does pixel_accuracy without a camera."""
        _at_most_one("tessellate", relative=relative, absolute=absolute, camera=camera)
        if pixel_accuracy is not None and camera is None:
            raise InvalidArgumentError("tessellate: pixel_accuracy needs a camera")
        request = tessellation_pb2.TessellateRequest(name=_mesh_name(mesh), encoding=_ENCODING[encoding])
        if relative is not None:
            request.relative = relative
        if absolute is not None:
            request.absolute = absolute
        if camera is not None:
            request.pixel.camera.CopyFrom(camera.to_proto())
            if pixel_accuracy is not None:
                request.pixel.pixel_accuracy = pixel_accuracy
        for name, value in (("eta", eta), ("uniform_level", uniform_level), ("max_triangles", max_triangles)):
            if value is not None:
                setattr(request, name, value)

        def attempt(t: Optional[float]) -> Tessellation:
            glb = bytearray()
            summary = None
            for response in self._tessellation.Tessellate(request, timeout=t, metadata=self._metadata):
                event = response.WhichOneof("event")
                if event == "progress" and progress:
                    progress(response.progress.stage, response.progress.fraction)
                elif event == "glb_chunk":
                    _append_chunk(glb, response.glb_chunk.offset, response.glb_chunk.data, "GLB")
                elif event == "summary":
                    summary = response.summary
            if summary is None:
                raise IntegrityError("the tessellation stream ended without its summary")
            return Tessellation(_check_received(glb, summary.glb_size, summary.glb_sha256, "GLB"), summary)

        return self._call(attempt, timeout)

    def tessellate_to_file(self, mesh: MeshRef, path: Union[str, Path], **kwargs) -> tessellation_pb2.TessellationSummary:
        """tessellate() into a file, written whole (through a temporary beside it) or not at all."""
        result = self.tessellate(mesh, **kwargs)
        path = Path(path)
        partial = path.with_name(path.name + ".partial")
        partial.write_bytes(result.glb)
        partial.replace(path)
        return result.summary

    # -- rendering ------------------------------------------------------------------------------

    def render(self, mesh: MeshRef, cameras: Sequence[Camera], pixel_accuracy: Optional[float] = None,
               absolute_tolerance: Optional[float] = None, uniform_level: Optional[int] = None,
               image_format: str = "png", crack_filling: Optional[bool] = None,
               timeout: Optional[float] = None) -> List[Frame]:
        """One frame per camera, in order, each checked against its header's size and sha256. At most
        one of pixel_accuracy, absolute_tolerance and uniform_level (InvalidArgumentError)."""
        _at_most_one("render", pixel_accuracy=pixel_accuracy, absolute_tolerance=absolute_tolerance,
                     uniform_level=uniform_level)
        settings = render_pb2.RenderSettings(format=_IMAGE_FORMAT[image_format])
        if pixel_accuracy is not None:
            settings.pixel_accuracy = pixel_accuracy
        if absolute_tolerance is not None:
            settings.absolute_tolerance = absolute_tolerance
        if uniform_level is not None:
            settings.uniform_level = uniform_level
        if crack_filling is not None:
            settings.crack_filling = crack_filling
        request = render_pb2.RenderRequest(name=_mesh_name(mesh), cameras=[c.to_proto() for c in cameras],
                                           settings=settings)

        def attempt(t: Optional[float]) -> List[Frame]:
            frames: List[Frame] = []
            image = bytearray()

            def finish() -> None:
                header = frames[-1].header
                frames[-1].image = _check_received(image, header.image_bytes, header.image_sha256,
                                                   f"frame {header.index}")

            for response in self._render.Render(request, timeout=t, metadata=self._metadata):
                if response.WhichOneof("event") == "header":
                    if frames:
                        finish()
                    frames.append(Frame(response.header, b""))
                    image.clear()
                elif not frames:
                    raise IntegrityError("an image chunk before any frame header")
                else:
                    _append_chunk(image, response.chunk.offset, response.chunk.data, f"frame {frames[-1].header.index}")
            if frames:
                finish()
            if len(frames) != len(cameras):
                raise IntegrityError(f"{len(frames)} frames received for {len(cameras)} cameras")
            return frames

        return self._call(attempt, timeout)

    # -- the server -----------------------------------------------------------------------------

    def health(self, service: str = "", timeout: Optional[float] = 5.0) -> str:
        """The serving status ("SERVING", "NOT_SERVING", ...) of the server or one of its services."""
        request = health_pb2.HealthCheckRequest(service=service)
        response = self._unary(self._health.Check, request, timeout)
        return health_pb2.HealthCheckResponse.ServingStatus.Name(response.status)

    def server_info(self, timeout: Optional[float] = 5.0) -> server_info_pb2.ServerInfo:
        request = server_info_pb2.GetServerInfoRequest()
        return self._unary(self._info.GetServerInfo, request, timeout)
