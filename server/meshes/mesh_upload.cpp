#include "server/meshes/mesh_upload.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/base/error.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/memory_estimates.h"
#include "core/topology/refinement_budget.h"
#include "core/topology/refinement_input.h"
#include "server/calls/status_error.h"
#include "server/meshes/mesh_names.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

constexpr size_t kMaxDisplayNameBytes = 256;
// Bytes each array element counts for against total_bytes (see UploadMeshHeader.total_bytes).
constexpr int64_t kScalarBytes = 4;
constexpr int64_t kCreaseBytes = 12;
constexpr int64_t kCornerBytes = 8;
constexpr int64_t kOriginBytes = 24;

int64_t arraysBytes(const v1::MeshArrays& a) {
  return kScalarBytes *
             (a.positions_size() + a.face_sizes_size() + a.face_vertices_size() + a.holes_size() + a.uvs_size() +
              a.uv_indices_size()) +
         kCreaseBytes * a.creases_size() + kCornerBytes * a.corners_size() + (a.has_origin() ? kOriginBytes : 0);
}

std::optional<BoundaryInterpolation> boundaryFromProto(int value) {
  switch (value) {
    case v1::BOUNDARY_INTERPOLATION_UNSPECIFIED:
      return std::nullopt;
    case v1::BOUNDARY_INTERPOLATION_EDGE_ONLY:
      return BoundaryInterpolation::kEdgeOnly;
    case v1::BOUNDARY_INTERPOLATION_EDGE_AND_CORNER:
      return BoundaryInterpolation::kEdgeAndCorner;
    case v1::BOUNDARY_INTERPOLATION_NONE:
      return BoundaryInterpolation::kNone;
  }
  throwInvalidArgument(
      fmt::format("header.options.boundary_interpolation: unknown value {}", value));
}

std::optional<CreaseMethod> creaseMethodFromProto(int value) {
  switch (value) {
    case v1::CREASE_METHOD_UNSPECIFIED:
      return std::nullopt;
    case v1::CREASE_METHOD_UNIFORM:
      return CreaseMethod::kUniform;
    case v1::CREASE_METHOD_CHAIKIN:
      return CreaseMethod::kChaikin;
  }
  throwInvalidArgument(fmt::format("header.options.crease_method: unknown value {}", value));
}

std::optional<TriangleSubdivision> triangleSubdivisionFromProto(int value) {
  switch (value) {
    case v1::TRIANGLE_SUBDIVISION_UNSPECIFIED:
      return std::nullopt;
    case v1::TRIANGLE_SUBDIVISION_CATMARK:
      return TriangleSubdivision::kCatmark;
    case v1::TRIANGLE_SUBDIVISION_SMOOTH:
      return TriangleSubdivision::kSmooth;
  }
  throwInvalidArgument(fmt::format("header.options.triangle_subdivision: unknown value {}", value));
}

std::optional<UvInterpolation> uvInterpolationFromProto(int value) {
  switch (value) {
    case v1::UV_INTERPOLATION_UNSPECIFIED: return std::nullopt;
    case v1::UV_INTERPOLATION_LINEAR_NONE: return UvInterpolation::kNone;
    case v1::UV_INTERPOLATION_LINEAR_CORNERS_ONLY: return UvInterpolation::kCornersOnly;
    case v1::UV_INTERPOLATION_LINEAR_CORNERS_PLUS1: return UvInterpolation::kCornersPlus1;
    case v1::UV_INTERPOLATION_LINEAR_CORNERS_PLUS2: return UvInterpolation::kCornersPlus2;
    case v1::UV_INTERPOLATION_LINEAR_BOUNDARIES: return UvInterpolation::kBoundaries;
    case v1::UV_INTERPOLATION_LINEAR_ALL: return UvInterpolation::kAll;
  }
  throwInvalidArgument(fmt::format("header.options.uv_interpolation: unknown value {}", value));
}

// A positions-only upload's topology comes from the mesh header.topology_of names: arrays that
// would describe another are refused rather than ignored.
void refuseTopologyArrays(const v1::MeshArrays& a, int64_t index, const std::string& topologyOf) {
  const char* field = a.face_sizes_size() > 0      ? "face_sizes"
                      : a.face_vertices_size() > 0 ? "face_vertices"
                      : a.creases_size() > 0       ? "creases"
                      : a.corners_size() > 0       ? "corners"
                      : a.holes_size() > 0         ? "holes"
                      : a.uv_indices_size() > 0    ? "uv_indices"
                                                   : nullptr;
  if (!field) return;
  throwInvalidArgument(fmt::format(
      "UploadMeshRequest #{}: arrays.{}: a positions-only upload takes its topology from {} "
      "(header.topology_of) and carries only positions, uvs and an origin",
      index, field, meshName(topologyOf)));
}

// core/ messages say what is wrong inside the mesh; the prefix says which upload part it is in.
[[noreturn]] void rethrowWithPrefix(const TesseraError& error, const std::string& prefix) {
  throw TesseraError(error.kind(), prefix + error.what());
}

}  // namespace

void UploadAssembler::accept(const v1::UploadMeshRequest& message) {
  const int64_t index = messages_++;
  const bool isHeader = message.payload_case() == v1::UploadMeshRequest::kHeader;
  if (index == 0 && !isHeader) {
    throwInvalidArgument("UploadMeshRequest #0: the first message must carry the header");
  }
  if (index == 0) return acceptHeader(message.header());
  switch (message.payload_case()) {
    case v1::UploadMeshRequest::kHeader:
      throwInvalidArgument(
          fmt::format("UploadMeshRequest #{}: the header was already sent in message #0", index));
    case v1::UploadMeshRequest::kObjData:
      if (metadata_.sourceFormat != SourceFormat::kObj) {
        throwInvalidArgument(fmt::format(
            "UploadMeshRequest #{}: obj_data in an upload whose header.format is ARRAYS", index));
      }
      countBytes(static_cast<int64_t>(message.obj_data().size()));
      obj_.append(message.obj_data());
      return;
    case v1::UploadMeshRequest::kArrays:
      if (metadata_.sourceFormat != SourceFormat::kArrays) {
        throwInvalidArgument(fmt::format(
            "UploadMeshRequest #{}: arrays in an upload whose header.format is OBJ", index));
      }
      if (!topologyOfId_.empty()) refuseTopologyArrays(message.arrays(), index, topologyOfId_);
      countBytes(arraysBytes(message.arrays()));
      acceptArrays(message.arrays());
      return;
    case v1::UploadMeshRequest::PAYLOAD_NOT_SET:
      throwInvalidArgument(fmt::format("UploadMeshRequest #{}: the message is empty", index));
  }
}

void UploadAssembler::acceptHeader(const v1::UploadMeshHeader& header) {
  requireMeshId(header.mesh_id(), "header.mesh_id");
  metadata_.id = header.mesh_id();
  if (header.display_name().size() > kMaxDisplayNameBytes) {
    throwInvalidArgument(fmt::format("header.display_name: {} bytes; at most {} are allowed",
                                     header.display_name().size(), kMaxDisplayNameBytes));
  }
  metadata_.displayName = header.display_name().empty() ? header.mesh_id() : header.display_name();
  switch (header.format()) {
    case v1::MESH_FORMAT_ARRAYS:
      metadata_.sourceFormat = SourceFormat::kArrays;
      break;
    case v1::MESH_FORMAT_OBJ:
      metadata_.sourceFormat = SourceFormat::kObj;
      break;
    default:
      throwInvalidArgument("header.format: must be MESH_FORMAT_ARRAYS or MESH_FORMAT_OBJ");
  }
  if (!header.topology_of().empty()) {
    topologyOfId_ = meshIdFromName(header.topology_of(), "header.topology_of");
    if (metadata_.sourceFormat != SourceFormat::kArrays) {
      throwInvalidArgument(
          "header.format: a positions-only upload (header.topology_of) must be MESH_FORMAT_ARRAYS");
    }
  }
  boundary_ = boundaryFromProto(header.options().boundary_interpolation());
  creaseMethod_ = creaseMethodFromProto(header.options().crease_method());
  triangleSubdivision_ = triangleSubdivisionFromProto(header.options().triangle_subdivision());
  uvInterpolation_ = uvInterpolationFromProto(header.options().uv_interpolation());
  if (header.total_bytes() <= 0) {
    throwInvalidArgument(
        fmt::format("header.total_bytes: must be positive (got {})", header.total_bytes()));
  }
  if (header.total_bytes() > limits_.maxUploadBytes) {
    throwResourceExhausted(
        fmt::format("header.total_bytes: {} bytes exceeds the server's max_upload_bytes of {}",
                    header.total_bytes(), limits_.maxUploadBytes));
  }
  // Arrays are counted in 4-byte units (kScalarBytes; creases 12, corners 8): no arrays upload
  // can add up to any other size.
  if (metadata_.sourceFormat == SourceFormat::kArrays && header.total_bytes() % kScalarBytes != 0) {
    throwInvalidArgument(fmt::format(
        "header.total_bytes: {} is not a multiple of 4; an ARRAYS upload counts 4 bytes per number",
        header.total_bytes()));
  }
  declaredBytes_ = header.total_bytes();
  metadata_.sourceBytes = declaredBytes_;
}

void UploadAssembler::countBytes(int64_t bytes) {
  if (bytes > declaredBytes_ - received_) {
    throwInvalidArgument(fmt::format(
        "UploadMeshRequest #{}: the data runs past header.total_bytes ({} bytes declared, at "
        "least {} sent)",
        messages_ - 1, declaredBytes_, received_ + bytes));
  }
  received_ += bytes;
}

void UploadAssembler::acceptArrays(const v1::MeshArrays& a) {
  positions_.insert(positions_.end(), a.positions().begin(), a.positions().end());
  arrays_.faceSizes.insert(arrays_.faceSizes.end(), a.face_sizes().begin(), a.face_sizes().end());
  arrays_.faceVertices.insert(arrays_.faceVertices.end(), a.face_vertices().begin(),
                              a.face_vertices().end());
  for (const v1::Crease& c : a.creases())
    arrays_.creases.push_back({c.v0(), c.v1(), c.sharpness()});
  for (const v1::Corner& c : a.corners()) arrays_.corners.push_back({c.vertex(), c.sharpness()});
  arrays_.holes.insert(arrays_.holes.end(), a.holes().begin(), a.holes().end());
  arrays_.uvs.insert(arrays_.uvs.end(), a.uvs().begin(), a.uvs().end());
  arrays_.uvIndices.insert(arrays_.uvIndices.end(), a.uv_indices().begin(), a.uv_indices().end());
  if (a.has_origin()) {
    if (hasOrigin_) throwInvalidArgument(fmt::format("UploadMeshRequest #{}: arrays.origin: given twice", messages_ - 1));
    const v1::Vec3& o = a.origin();
    if (!std::isfinite(o.x()) || !std::isfinite(o.y()) || !std::isfinite(o.z())) {
      throwInvalidArgument(fmt::format("UploadMeshRequest #{}: arrays.origin: not finite", messages_ - 1));
    }
    arrays_.origin = Vec3d(o.x(), o.y(), o.z());
    hasOrigin_ = true;
  }
}

AssembledUpload UploadAssembler::finish(const ControlMesh* topology) {
  if (!hasHeader()) throwInvalidArgument("UploadMesh: the stream ended before the header");
  if (received_ != declaredBytes_) {
    throwInvalidArgument(
        fmt::format("UploadMesh: upload truncated: received {} of the {} bytes declared in "
                    "header.total_bytes",
                    received_, declaredBytes_));
  }
  if (!topologyOfId_.empty() && !topology) {
    throw std::logic_error("UploadAssembler::finish: a positions-only upload needs its topology");
  }
  ControlMesh mesh = !topologyOfId_.empty()                          ? buildOnTopology(*topology)
                     : metadata_.sourceFormat == SourceFormat::kObj ? parseObj()
                                                                    : buildFromArrays();
  const std::string where = metadata_.sourceFormat == SourceFormat::kObj
                                ? metadata_.displayName + ": "
                                : std::string("arrays: ");
  int64_t refined = 0;
  try {
    validateControlMesh(mesh, limits_.mesh);
    refined = requireRefinementWithin(RefinementInput(mesh).unholed(), limits_.maxRefinedVertices, {});
  } catch (const TesseraError& error) {
    rethrowWithPrefix(error, where);
  }
  // The refinement as estimated, and the part that does not depend on it.
  const int64_t preprocessing = std::max(refinementBytes(refined), preprocessingBytes(mesh, 0));
  return AssembledUpload{std::move(mesh), metadata_, preprocessing, where};
}

ControlMesh UploadAssembler::buildFromArrays() {
  if (positions_.size() % 3 != 0) {
    throwInvalidArgument(fmt::format(
        "arrays.positions: {} floats is not a whole number of x, y, z triples", positions_.size()));
  }
  ControlMesh mesh = std::move(arrays_);
  mesh.positions.resize(positions_.size() / 3);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    mesh.positions[i] = Vec3(positions_[3 * i], positions_[3 * i + 1], positions_[3 * i + 2]);
  }
  positions_ = {};
  overrideRules(mesh);
  return mesh;
}

// The stored mesh's faces, tags, rules and UV indices with the upload's positions, its UV values
// if it sent any, and its origin: the mesh a full upload of the same arrays would make.
ControlMesh UploadAssembler::buildOnTopology(const ControlMesh& topology) {
  const std::string shared = meshName(topologyOfId_) + " (header.topology_of)";
  const size_t vertices = topology.positions.size();
  if (positions_.size() != 3 * vertices) {
    throwInvalidArgument(fmt::format("arrays.positions: {} floats, where {} has {} vertices: {} floats are needed",
                                     positions_.size(), shared, vertices, 3 * vertices));
  }
  if (!arrays_.uvs.empty() && arrays_.uvs.size() != topology.uvs.size()) {
    throwInvalidArgument(
        topology.uvs.empty()
            ? fmt::format("arrays.uvs: {} numbers, where {} has no UVs", arrays_.uvs.size(), shared)
            : fmt::format("arrays.uvs: {} numbers, where {} has {} UV numbers ({} UVs): send all of them, "
                          "or none to keep its own",
                          arrays_.uvs.size(), shared, topology.uvs.size(), topology.uvs.size() / 2));
  }
  ControlMesh mesh = topology;
  for (size_t i = 0; i < vertices; ++i) {
    mesh.positions[i] = Vec3(positions_[3 * i], positions_[3 * i + 1], positions_[3 * i + 2]);
  }
  positions_ = {};
  if (!arrays_.uvs.empty()) mesh.uvs = std::move(arrays_.uvs);
  mesh.origin = hasOrigin_ ? arrays_.origin : Vec3d(0, 0, 0);
  overrideRules(mesh);
  if (!(mesh.rules == topology.rules)) {
    throwInvalidArgument(fmt::format("header.options: differ from the rules of {}, whose topology this upload "
                                     "shares; leave them unset to take its rules",
                                     shared));
  }
  return mesh;
}

ControlMesh UploadAssembler::parseObj() {
  ControlMesh mesh = readObj(obj_, metadata_.displayName, limits_.mesh);
  obj_ = {};
  overrideRules(mesh);
  return mesh;
}

// Rules the header names replace the source's (an OBJ's tags; OpenSubdiv's defaults for arrays).
void UploadAssembler::overrideRules(ControlMesh& mesh) const {
  if (boundary_) mesh.rules.boundary = *boundary_;
  if (creaseMethod_) mesh.rules.creaseMethod = *creaseMethod_;
  if (triangleSubdivision_) mesh.rules.triangleSubdivision = *triangleSubdivision_;
  if (uvInterpolation_) mesh.rules.uvInterpolation = *uvInterpolation_;
}

}  // namespace tessera::server
