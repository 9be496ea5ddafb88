#include "server/meshes/mesh_proto.h"

#include <algorithm>

#include "core/mesh/mesh_codec.h"
#include "core/mesh/subdivision_rules.h"
#include "server/calls/status_error.h"
#include "server/meshes/mesh_names.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

constexpr std::string_view kPageTokenPrefix = "after:";

void toProto(const Vec3d& v, v1::Vec3* out) {
  out->set_x(v.x);
  out->set_y(v.y);
  out->set_z(v.z);
}

std::string toHex(std::string_view bytes) {
  constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned char c : bytes) {
    hex += kHex[c >> 4];
    hex += kHex[c & 15];
  }
  return hex;
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

[[noreturn]] void badToken() {
  throwInvalidArgument("page_token: not a token returned by ListMeshes");
}

// Appends elements [begin, begin + count) of one array to the chunk through add.
template <typename Add>
void appendRange(size_t begin, size_t count, Add add) {
  for (size_t i = begin; i < begin + count; ++i) add(i);
}

v1::UvInterpolation uvInterpolationToProto(UvInterpolation rule) {
  switch (rule) {
    case UvInterpolation::kNone: return v1::UV_INTERPOLATION_LINEAR_NONE;
    case UvInterpolation::kCornersOnly: return v1::UV_INTERPOLATION_LINEAR_CORNERS_ONLY;
    case UvInterpolation::kCornersPlus1: return v1::UV_INTERPOLATION_LINEAR_CORNERS_PLUS1;
    case UvInterpolation::kCornersPlus2: return v1::UV_INTERPOLATION_LINEAR_CORNERS_PLUS2;
    case UvInterpolation::kBoundaries: return v1::UV_INTERPOLATION_LINEAR_BOUNDARIES;
    case UvInterpolation::kAll: break;
  }
  return v1::UV_INTERPOLATION_LINEAR_ALL;
}

}  // namespace

void toProto(const MeshMetadata& m, v1::Mesh* out) {
  out->set_name(meshName(m.id));
  out->set_display_name(m.displayName);
  out->set_source_format(static_cast<v1::MeshFormat>(m.sourceFormat));
  out->set_source_bytes(m.sourceBytes);
  out->mutable_options()->set_boundary_interpolation(
      static_cast<v1::BoundaryInterpolation>(boundaryCode(m.rules.boundary)));
  out->mutable_options()->set_crease_method(m.rules.creaseMethod == CreaseMethod::kChaikin
                                                ? v1::CREASE_METHOD_CHAIKIN
                                                : v1::CREASE_METHOD_UNIFORM);
  out->mutable_options()->set_triangle_subdivision(m.rules.triangleSubdivision ==
                                                           TriangleSubdivision::kSmooth
                                                       ? v1::TRIANGLE_SUBDIVISION_SMOOTH
                                                       : v1::TRIANGLE_SUBDIVISION_CATMARK);
  out->mutable_options()->set_uv_interpolation(uvInterpolationToProto(m.rules.uvInterpolation));
  out->set_vertex_count(m.vertexCount);
  out->set_face_count(m.faceCount);
  out->set_face_vertex_count(m.faceVertexCount);
  out->set_crease_count(m.creaseCount);
  out->set_corner_count(m.cornerCount);
  out->set_hole_count(m.holeCount);
  toProto(m.boundsMin, out->mutable_bounding_box()->mutable_min());
  toProto(m.boundsMax, out->mutable_bounding_box()->mutable_max());
  out->set_sha256(m.sha256);
  out->mutable_create_time()->set_seconds(m.createTimeMicros / 1'000'000);
  out->mutable_create_time()->set_nanos(static_cast<int32_t>(m.createTimeMicros % 1'000'000) *
                                        1000);
  out->set_stored_bytes(m.storedBytes);
}

std::string encodePageToken(const std::string& lastId) {
  return toHex(std::string(kPageTokenPrefix) + lastId);
}

std::string decodePageToken(const std::string& token) {
  if (token.size() % 2 != 0) badToken();
  std::string raw;
  for (size_t i = 0; i < token.size(); i += 2) {
    int hi = hexValue(token[i]), lo = hexValue(token[i + 1]);
    if (hi < 0 || lo < 0) badToken();
    raw += static_cast<char>(hi * 16 + lo);
  }
  if (raw.substr(0, kPageTokenPrefix.size()) != kPageTokenPrefix) badToken();
  std::string id = raw.substr(kPageTokenPrefix.size());
  if (!isValidMeshId(id)) badToken();
  return id;
}

bool forEachArraysChunk(const ControlMesh& mesh, size_t maxBytes,
                        const std::function<bool(const v1::MeshArrays&)>& emit) {
  // Each message carries a run of at most `per` elements of one array (12 bytes is the largest
  // element), arrays in upload order, so every message stays under maxBytes.
  const size_t per = std::max<size_t>(maxBytes / 12, 1);
  v1::MeshArrays chunk;
  auto flush = [&]() {
    if (chunk.ByteSizeLong() == 0) return true;
    bool more = emit(chunk);
    chunk.Clear();
    return more;
  };
  auto sendRuns = [&](size_t total, auto add) {
    for (size_t begin = 0; begin < total; begin += per) {
      appendRange(begin, std::min(per, total - begin), add);
      if (!flush()) return false;
    }
    return true;
  };
  return sendRuns(mesh.positions.size(),
                  [&](size_t i) {
                    const Vec3& p = mesh.positions[i];
                    chunk.add_positions(p.x), chunk.add_positions(p.y), chunk.add_positions(p.z);
                  }) &&
         sendRuns(mesh.faceSizes.size(),
                  [&](size_t i) { chunk.add_face_sizes(mesh.faceSizes[i]); }) &&
         sendRuns(mesh.faceVertices.size(),
                  [&](size_t i) { chunk.add_face_vertices(mesh.faceVertices[i]); }) &&
         sendRuns(mesh.creases.size(),
                  [&](size_t i) {
                    v1::Crease* c = chunk.add_creases();
                    c->set_v0(mesh.creases[i].v0);
                    c->set_v1(mesh.creases[i].v1);
                    c->set_sharpness(mesh.creases[i].sharpness);
                  }) &&
         sendRuns(mesh.corners.size(),
                  [&](size_t i) {
                    v1::Corner* c = chunk.add_corners();
                    c->set_vertex(mesh.corners[i].vertex);
                    c->set_sharpness(mesh.corners[i].sharpness);
                  }) &&
         sendRuns(mesh.holes.size(), [&](size_t i) { chunk.add_holes(mesh.holes[i]); }) &&
         sendRuns(mesh.uvs.size(), [&](size_t i) { chunk.add_uvs(mesh.uvs[i]); }) &&
         sendRuns(mesh.uvIndices.size(), [&](size_t i) { chunk.add_uv_indices(mesh.uvIndices[i]); }) &&
         sendRuns(mesh.hasOrigin() ? 1 : 0, [&](size_t) {
           toProto(mesh.origin, chunk.mutable_origin());
         });
}

}  // namespace tessera::server
