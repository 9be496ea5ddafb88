// The uniform-grid cases the CPU-side simulation and the device test both run, with the CPU's
// samples to match: bigguy (regular patches, rings of several depths) and car (deep isolation,
// mostly N = 1), at levels 64 (sides 65 down to 2), 15 and 1.
#pragma once

#include <string>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/uniform/uniform_grid.h"
#include "reference/models.h"

namespace tessera::cuda::testing {

// Calls check(name, p, patches, grid, expected) for every case.
template <class Check>
void forEachGridCase(GridKernel reference, Check&& check) {
  for (const char* name : {"bigguy", "car"}) {
    const PatchSet patches =
        buildPatchSet(readObjFile(tessera::testing::modelsDir() + "/" + name + ".obj"));
    for (int p : {64, 15, 1}) {
      UniformGrid grid;
      planUniformGrid(patches, p, grid);
      std::vector<Vec3> expected(grid.samples());
      evaluateUniformGrid(patches, grid, expected.data(), reference);
      check(std::string(name), p, patches, grid, expected);
    }
  }
}

}  // namespace tessera::cuda::testing
