// Assembles one UploadMesh stream into a validated control mesh. It checks the protocol (header
// first and once, chunks of the declared format, exactly total_bytes of data), then parses and
// validates the mesh with core/. A positions-only upload (header.topology_of) is completed from
// the mesh it names, whose topology the caller looks up and hands to finish(). Every refusal is a StatusError or TesseraError whose message
// names the field, the message number or the OBJ line. Holds at most total_bytes of data, which
// the header check bounds by the server's upload limit before anything is buffered.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "server/meshes/mesh_metadata.h"
#include "tessera/v1/mesh.pb.h"

namespace tessera::server {

struct UploadLimits {
  int64_t maxUploadBytes = 256 << 20;
  MeshLimits mesh;
  // OpenSubdiv's adaptive refinement of a mesh (core/topology/refinement_budget.h): ~650 bytes of patch set
  // per vertex, so the default bounds preprocessing at ~2.6 GB. Checked at upload and again when
  // a mesh is preprocessed.
  int64_t maxRefinedVertices = 4'000'000;
};

struct AssembledUpload {
  ControlMesh mesh;
  // id, displayName, sourceFormat and sourceBytes; the rest is filled when it is stored.
  MeshMetadata metadata;
  // What preprocessing the mesh is sure to reserve (core/pipeline/memory_estimates.h): the caller refuses
  // a mesh that could never fit the server's memory budget (admission_control.h).
  int64_t preprocessingBytes = 0;
  std::string where;  // the mesh in messages: "NAME: " or "arrays: "
};

class UploadAssembler {
 public:
  explicit UploadAssembler(const UploadLimits& limits) : limits_(limits) {}

  // The next message of the stream.
  void accept(const tessera::v1::UploadMeshRequest& message);
  bool hasHeader() const { return messages_ > 0; }
  const std::string& meshId() const { return metadata_.id; }
  int64_t receivedBytes() const { return received_; }
  // The id of the mesh header.topology_of names; empty for an ordinary upload.
  const std::string& topologyOfId() const { return topologyOfId_; }

  // After the client's last message: checks the byte count, then parses and validates (the
  // expensive part, which the caller runs under admission control). A positions-only upload
  // needs `topology`, the stored mesh topologyOfId() names: its positions and UV values are
  // replaced by the upload's after their counts are checked against it.
  AssembledUpload finish(const ControlMesh* topology = nullptr);

 private:
  void acceptHeader(const tessera::v1::UploadMeshHeader& header);
  void acceptArrays(const tessera::v1::MeshArrays& arrays);
  void countBytes(int64_t bytes);
  ControlMesh buildFromArrays();
  ControlMesh buildOnTopology(const ControlMesh& topology);
  ControlMesh parseObj();
  void overrideRules(ControlMesh& mesh) const;

  UploadLimits limits_;
  MeshMetadata metadata_;
  // Unset: the source's (the OBJ's tags, or OpenSubdiv's defaults for arrays).
  std::optional<BoundaryInterpolation> boundary_;
  std::optional<CreaseMethod> creaseMethod_;
  std::optional<TriangleSubdivision> triangleSubdivision_;
  std::optional<UvInterpolation> uvInterpolation_;
  bool hasOrigin_ = false;
  std::string topologyOfId_;
  int64_t declaredBytes_ = 0;
  int64_t received_ = 0;
  int64_t messages_ = 0;
  std::string obj_;
  std::vector<float> positions_;
  ControlMesh arrays_;  // everything but the positions, which arrive as loose floats
};

}  // namespace tessera::server
