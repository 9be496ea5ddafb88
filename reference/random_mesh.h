// Random control meshes, the topologies nobody models on purpose but uploads happen to contain:
// 4–15 vertices, 1–10 faces of 3–5 random corners (so faces that repeat a vertex, fold back along
// an edge they left by, collapse an edge to a point, meet an edge twice, and non-manifold edges
// and vertices), random holes, boundary rules and a crease. One seed, one mesh, on every machine
// (std::mt19937 is fully specified). tests/random_topology_test.cpp and tools/random_topology
// use them.
#pragma once

#include <cstdint>
#include <string>

#include "core/mesh/control_mesh.h"
#include "core/pipeline/tessellate.h"
#include "reference/limit_distance.h"

namespace tessera::testing {

ControlMesh randomMesh(uint32_t seed);

// Tessera's mesh at `relative` of the diagonal, parameters recorded; throws TesseraError where
// Tessera refuses the mesh.
TessellationResult tessellateRandom(const ControlMesh& mesh, double relative);

// Random mesh `seed` tessellated at `relative` and measured two-sided against Far's limit surface
// of the input (Debian's Bfr 3.5.0 mis-evaluates, and once crashes on, such input), mesh samples
// the kd-tree's seeds leave over the tolerance projected from every domain.
struct RandomMeshCheck {
  std::string refused;   // Tessera's message where it refused the mesh
  bool empty = false;    // every face a hole: nothing to measure
  double tolerance = 0;  // ε plus the reference's accuracy, object units
  LimitDistanceReport report;
  bool measured() const { return refused.empty() && !empty; }
};
RandomMeshCheck checkRandomMesh(uint32_t seed, double relative);

}  // namespace tessera::testing
