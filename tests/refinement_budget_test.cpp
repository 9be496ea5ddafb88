// The refinement budget (core/topology/refinement_budget.h) against OpenSubdiv's complete refinement: it
// admits the real models at the server's default, refuses a mesh whose creases would refine it
// into gigabytes before refining it, and agrees with the exact count where it refines to the end.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "core/base/error.h"
#include "core/mesh/obj_reader.h"
#include "core/topology/far_topology.h"
#include "core/topology/refinement_budget.h"
#include "reference/models.h"

namespace tessera {
namespace {

constexpr int64_t kServerDefault = 4'000'000;  // server/meshes/mesh_upload.h

ControlMesh model(const std::string& name) { return readObjFile(testing::modelsDir() + "/" + name + ".obj"); }

// Every edge of the mesh made a semi-sharp crease.
ControlMesh creasedEverywhere(ControlMesh mesh, float sharpness) {
  std::set<std::pair<int, int>> edges;
  size_t start = 0;
  for (int size : mesh.faceSizes) {
    for (int k = 0; k < size; ++k) {
      const int a = mesh.faceVertices[start + k], b = mesh.faceVertices[start + (k + 1) % size];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
    start += size_t(size);
  }
  for (const auto& [a, b] : edges) mesh.creases.push_back({a, b, sharpness});
  return mesh;
}

int64_t completeRefinement(const ControlMesh& mesh) {
  auto refiner = createTopologyRefiner(mesh);
  refineAdaptively(*refiner, patchTableOptions(isolationLevelFor(mesh)));
  return refiner->GetNumVerticesTotal();
}

TEST(RefinementBudget, AdmitsTheModelsAtTheServersDefault) {
  for (const char* name : {"bigguy", "monsterfrog", "armorguy", "t-rex", "car", "opensubdiv-shapes/catmark_rook",
                           "opensubdiv-shapes/catmark_bishop"}) {
    EXPECT_NO_THROW(requireRefinementWithin(model(name), kServerDefault, {})) << name;
  }
}

// 2,900 edges at sharpness 9.5: ten levels of isolation, ~40 million vertices if refined.
TEST(RefinementBudget, RefusesCreasesThatWouldRefineTheMeshIntoGigabytes) {
  const ControlMesh mesh = creasedEverywhere(model("bigguy"), 9.5f);
  try {
    requireRefinementWithin(mesh, kServerDefault, {});
    FAIL() << "accepted";
  } catch (const TesseraError& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kLimitExceeded);
    EXPECT_NE(std::string(error.what()).find("over the limit of 4000000 (max_refined_vertices)"), std::string::npos)
        << error.what();
  }
}

TEST(RefinementBudget, AgreesWithTheCompleteRefinementAtItsLimit) {
  const ControlMesh mesh = creasedEverywhere(model("bigguy"), 3.5f);
  const int64_t exact = completeRefinement(mesh);
  ASSERT_GT(exact, 100'000);
  EXPECT_NO_THROW(requireRefinementWithin(mesh, exact, {}));
  EXPECT_THROW(requireRefinementWithin(mesh, exact - 1, {}), TesseraError);
}

TEST(RefinementBudget, RunsTheCheckpointBetweenRefinements) {
  int calls = 0;
  requireRefinementWithin(creasedEverywhere(model("bigguy"), 3.5f), kServerDefault, [&] { ++calls; });
  EXPECT_GE(calls, 1);
  EXPECT_THROW(requireRefinementWithin(model("bigguy"), kServerDefault, [] { throw std::runtime_error("stop"); }),
               std::runtime_error);
}

}  // namespace
}  // namespace tessera
