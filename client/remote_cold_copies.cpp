#include "client/remote_cold_copies.h"

#include <cmath>
#include <numbers>

#include "client/remote_mesh_download.h"

namespace tessera::cli {
namespace {

// Waves across the mesh: two periods over the diagonal, smooth at the scale of its faces.
constexpr double kWavesPerDiagonal = 2;

// Phases from the index by the fractional parts of multiples of irrational numbers (Weyl
// sequences): never equal for two indices, and spread over the period.
double phase(uint64_t index, double step) {
  const double turns = double(index + 1) * step;
  return 2 * std::numbers::pi * (turns - std::floor(turns));
}

}  // namespace

grpc::Status readColdSource(tessera::v1::MeshService::Stub& stub, grpc::ClientContext& context,
                            const std::string& name, ColdSource* source) {
  tessera::v1::Mesh mesh;
  source->name = name;
  const grpc::Status status = downloadMesh(stub, context, name, &mesh, &source->arrays);
  const tessera::v1::BoundingBox& box = mesh.bounding_box();
  const double dx = box.max().x() - box.min().x(), dy = box.max().y() - box.min().y(),
               dz = box.max().z() - box.min().z();
  source->diagonal = std::sqrt(dx * dx + dy * dy + dz * dz);
  source->options = mesh.options();
  return status;
}

tessera::v1::MeshArrays coldCopy(const ColdSource& source, uint64_t index) {
  tessera::v1::MeshArrays copy = source.arrays;
  const double diagonal = source.diagonal;
  const double amplitude = kColdDisplacement * diagonal;
  const double frequency = 2 * std::numbers::pi * kWavesPerDiagonal / diagonal;
  const double phases[3] = {phase(index, std::numbers::sqrt2), phase(index, std::numbers::sqrt3),
                            phase(index, std::numbers::phi)};
  auto& positions = *copy.mutable_positions();
  for (int v = 0; v + 2 < positions.size(); v += 3) {
    const double p[3] = {positions[v], positions[v + 1], positions[v + 2]};
    // Each axis moves with the next one's coordinate, so the field is not a rigid shift.
    for (int axis = 0; axis < 3; ++axis) {
      positions[v + axis] =
          float(p[axis] + amplitude * std::sin(frequency * p[(axis + 1) % 3] + phases[axis]));
    }
  }
  return copy;
}

}  // namespace tessera::cli
