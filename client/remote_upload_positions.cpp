#include "client/remote_upload_positions.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>

namespace tessera::cli {
namespace {

namespace v1 = tessera::v1;

// The first index where two arrays of one kind differ, or where one ends; -1 if they agree.
template <typename Local, typename Stored, typename Same>
int64_t firstDifference(const Local& local, const Stored& stored, Same same) {
  const int64_t n = std::min<int64_t>(std::ssize(local), stored.size());
  for (int64_t i = 0; i < n; ++i) {
    if (!same(local[size_t(i)], stored[int(i)])) return i;
  }
  return std::ssize(local) == int64_t(stored.size()) ? -1 : n;
}

template <typename Local, typename Stored, typename Same>
void requireSame(const char* what, const Local& local, const Stored& stored, Same same,
                 const std::string& source, const std::string& name) {
  if (std::ssize(local) != int64_t(stored.size())) {
    throw TopologyMismatch(fmt::format("{} has {} {}, {} has {}: not its topology", source,
                                       std::ssize(local), what, name, stored.size()));
  }
  if (const int64_t at = firstDifference(local, stored, same); at >= 0) {
    throw TopologyMismatch(fmt::format("{} differs from {} in its {} at index {}: not its topology",
                                       source, name, what, at));
  }
}

v1::SubdivisionOptions optionsOf(const SubdivisionRules& r) {
  v1::SubdivisionOptions o;
  o.set_boundary_interpolation(r.boundary == BoundaryInterpolation::kEdgeAndCorner
                                   ? v1::BOUNDARY_INTERPOLATION_EDGE_AND_CORNER
                               : r.boundary == BoundaryInterpolation::kNone
                                   ? v1::BOUNDARY_INTERPOLATION_NONE
                                   : v1::BOUNDARY_INTERPOLATION_EDGE_ONLY);
  o.set_crease_method(r.creaseMethod == CreaseMethod::kChaikin ? v1::CREASE_METHOD_CHAIKIN
                                                               : v1::CREASE_METHOD_UNIFORM);
  o.set_triangle_subdivision(r.triangleSubdivision == TriangleSubdivision::kSmooth
                                 ? v1::TRIANGLE_SUBDIVISION_SMOOTH
                                 : v1::TRIANGLE_SUBDIVISION_CATMARK);
  // The proto lists the rules from LINEAR_NONE = 1 in the order UvInterpolation lists them after
  // kAll; LINEAR_ALL is 6.
  o.set_uv_interpolation(r.uvInterpolation == UvInterpolation::kAll
                             ? v1::UV_INTERPOLATION_LINEAR_ALL
                             : v1::UvInterpolation(int(r.uvInterpolation)));
  return o;
}

}  // namespace

v1::MeshArrays positionsOnlyArrays(const ControlMesh& local, const std::string& source,
                                   const std::string& name, const v1::MeshArrays& stored,
                                   v1::SubdivisionOptions* rules) {
  auto equal = [](auto a, auto b) { return a == b; };
  if (int64_t(local.positions.size()) * 3 != stored.positions_size()) {
    throw TopologyMismatch(fmt::format("{} has {} vertices, {} has {}: not its topology", source,
                                       local.positions.size(), name, stored.positions_size() / 3));
  }
  requireSame("faces", local.faceSizes, stored.face_sizes(), equal, source, name);
  requireSame("face vertices", local.faceVertices, stored.face_vertices(), equal, source, name);
  requireSame(
      "creases", local.creases, stored.creases(),
      [](const CreaseEdge& a, const v1::Crease& b) {
        return a.v0 == b.v0() && a.v1 == b.v1() && a.sharpness == b.sharpness();
      },
      source, name);
  requireSame(
      "corners", local.corners, stored.corners(),
      [](const CornerVertex& a, const v1::Corner& b) {
        return a.vertex == b.vertex() && a.sharpness == b.sharpness();
      },
      source, name);
  requireSame("holes", local.holes, stored.holes(), equal, source, name);
  requireSame("UV indices", local.uvIndices, stored.uv_indices(), equal, source, name);
  if (local.uvs.size() != size_t(stored.uvs_size())) {
    throw TopologyMismatch(fmt::format("{} has {} UVs, {} has {}: not its topology", source,
                                       local.uvs.size() / 2, name, stored.uvs_size() / 2));
  }
  *rules = optionsOf(local.rules);
  v1::MeshArrays arrays;
  arrays.mutable_positions()->Reserve(int(3 * local.positions.size()));
  for (const Vec3& p : local.positions) {
    arrays.add_positions(p.x), arrays.add_positions(p.y), arrays.add_positions(p.z);
  }
  // Bit for bit: a UV that reads back as another float is a change.
  const auto sameBits = [](float a, float b) {
    return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
  };
  if (firstDifference(local.uvs, stored.uvs(), sameBits) >= 0)
    arrays.mutable_uvs()->Add(local.uvs.begin(), local.uvs.end());
  if (local.hasOrigin()) {
    arrays.mutable_origin()->set_x(local.origin.x), arrays.mutable_origin()->set_y(local.origin.y);
    arrays.mutable_origin()->set_z(local.origin.z);
  }
  return arrays;
}

}  // namespace tessera::cli
