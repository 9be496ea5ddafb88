// Random control meshes (reference/random_mesh.h) over a range of seeds at one tolerance:
// Tessera's mesh measured two-sided against Far's limit surface of the input, as
// RandomTopology.* does for its first seeds. Prints each mesh over ε and a summary; the figures
// of docs/NONMANIFOLD.md ("Beyond the shared shapes") come from it.
//   tessera-random-topology --from 0 --to 2400 --relative 1e-2
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>

#include "reference/random_mesh.h"

int main(int argc, char** argv) {
  CLI::App app{"Random topologies against Far's limit surface"};
  uint32_t from = 0, to = 400;
  double relative = 1e-2;
  app.add_option("--from", from, "first seed");
  app.add_option("--to", to, "one past the last seed");
  app.add_option("--relative", relative, "tolerance, relative to the control mesh's diagonal")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  int measured = 0, over = 0, refused = 0;
  for (uint32_t seed = from; seed < to; ++seed) {
    const tessera::testing::RandomMeshCheck check = tessera::testing::checkRandomMesh(seed, relative);
    refused += !check.refused.empty();
    if (!check.measured()) continue;
    ++measured;
    const tessera::testing::LimitDistanceReport& r = check.report;
    if (r.twoSided() <= check.tolerance) continue;
    ++over;
    const double epsilon = relative * r.diagonal;
    std::printf("seed %u: %.3f ε (mesh -> limit %.3f at face %d/%d (%.3f, %.3f); limit -> mesh %.3f)\n", seed,
                r.twoSided() / epsilon, r.meshToLimit / epsilon, r.meshToLimitAt.face, r.meshToLimitAt.subFace,
                r.meshToLimitAt.u, r.meshToLimitAt.v, r.limitToMesh / epsilon);
  }
  std::printf("seeds %u..%u at %g: %d measured, %d over ε, %d refused\n", from, to - 1, relative, measured, over, refused);
  return 0;
}
