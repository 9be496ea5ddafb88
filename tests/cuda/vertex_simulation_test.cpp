// The vertex kernel's algorithm run on the CPU: gpu/cuda/vertex_threads.h compiled by the host
// compiler over the arrays makeSurfaceUpload copies to the device, one call per thread in
// shuffled order into NaN-poisoned output, as the evaluation of a whole tessellation. Its mesh
// must equal the CPU engine's bit for bit, so a leaf read from the wrong array, a FAS net gathered
// or centred wrongly, a thread missed or a request mapped to the wrong tile fails. Runs on every
// machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

#include "core/pipeline/preprocessing.h"
#include "core/surface/adaptive_surface.h"
#include "gpu/cuda/surface_upload.h"
#include "gpu/cuda/vertex_threads.h"
#include "tests/cuda/vertex_cases.h"
#include "tests/support/mesh_equality.h"

namespace tessera::cuda {
namespace {

class SimulatedVertexEvaluation : public VertexEvaluation {
 public:
  explicit SimulatedVertexEvaluation(const PatchSet& patches) : upload_(makeSurfaceUpload(patches)) {}

  bool evaluate(const AdaptivePlan& plan, const Stitching& stitching, std::vector<Vec3>& positions,
                std::vector<Vec3>& normals) override {
    std::vector<NodeSquare> tileNodes;
    for (const Tile& tile : plan.tiles) tileNodes.push_back(tile.node);
    const float poison = std::numeric_limits<float>::quiet_NaN();
    std::fill(positions.begin(), positions.end(), Vec3(poison, poison, poison));
    std::fill(normals.begin(), normals.end(), Vec3(poison, poison, poison));
    const VertexView view{upload_.view(), tileNodes.data(), stitching.vertices.data(), stitching.vertices.size(),
                          positions.data(), normals.data()};
    std::vector<uint64_t> threads(view.count);
    std::iota(threads.begin(), threads.end(), 0);
    std::shuffle(threads.begin(), threads.end(), random_);
    for (uint64_t i : threads) evaluateVertex(view, i);
    ++calls;
    return true;
  }

  int calls = 0;

 private:
  SurfaceUpload upload_;
  std::mt19937 random_{11};
};

void expectSimulationMatchesCpu(const testing::VertexCase& c) {
  const ControlMesh mesh = testing::readCaseMesh(c.path);
  if (mesh.faceCount() == 0) return;  // refused by the reader (covered by PatchSet's tests)
  const PatchSet patches = buildPatchSet(mesh);
  SimulatedVertexEvaluation simulated(patches);
  const TessellationResult cpu = tessellate(patches, mesh, testing::vertexCaseOptions(c.tolerance, nullptr));
  const TessellationResult kernel = tessellate(patches, mesh, testing::vertexCaseOptions(c.tolerance, &simulated));
  EXPECT_EQ(simulated.calls, 1) << c.path;
  EXPECT_EQ(tessera::testing::meshDifference(kernel.mesh, cpu.mesh), "")
      << tessera::testing::baseName(c.path) << " at " << c.tolerance << " (" << cpu.mesh.positions.size()
      << " vertices)";
}

TEST(VertexSimulation, EqualsTheCpuEngineOnEveryShape) {
  for (const testing::VertexCase& c : testing::vertexCases(false)) expectSimulationMatchesCpu(c);
}

TEST(VertexSimulation, EqualsTheCpuEngineOnThePapersCharacters) {
  for (const testing::VertexCase& c : testing::vertexCases(true)) expectSimulationMatchesCpu(c);
}

// The upload holds every leaf's net where the kernel looks: an EV bottom, FAS leaves and regular
// patches each present in a shape that has them.
TEST(VertexSimulation, UploadHoldsEveryLeafKind) {
  const PatchSet patches =
      buildPatchSet(readObjFile(tessera::testing::modelsDir() + "/opensubdiv-shapes/catmark_pole8.obj"));
  const SurfaceUpload upload = makeSurfaceUpload(patches);
  const SurfaceTree& tree = patches.adaptive->tree;
  EXPECT_EQ(upload.nodes.size(), tree.nodes.size());
  EXPECT_EQ(upload.regularNets.size(), 16 * patches.regular.size());
  EXPECT_EQ(upload.fasNets.size(), 16 * tree.fasLeaves.size());
  EXPECT_EQ(upload.fasCenters.size(), tree.fasLeaves.size());
  EXPECT_GT(tree.fasLeaves.size(), 0u);
  EXPECT_GT(upload.evBottoms.size(), 0u);
  EXPECT_GT(upload.regularNets.size(), 0u);
}

}  // namespace
}  // namespace tessera::cuda
