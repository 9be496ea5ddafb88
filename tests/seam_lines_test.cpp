// The lines roots share (core/surface/seam_lines.h), listed by the root of their first side.
#include "core/surface/seam_lines.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/surface/adaptive_surface.h"
#include "reference/models.h"

namespace tessera {
namespace {

// Every line once, under the root of its first side, which is its lowest (rootSides ascend).
void expectLinesByTheirFirstRoot(const std::string& shape) {
  SCOPED_TRACE(shape);
  const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/" + shape + ".obj");
  const PatchSet patches = buildPatchSet(mesh);
  const SeamLines& lines = patches.adaptive->lines;
  const size_t roots = patches.adaptive->tree.roots.size();
  ASSERT_EQ(lines.rootFirstLine.size(), roots + 1);
  ASSERT_EQ(lines.linesByRoot.size(), lines.lines.size());
  std::vector<int> listed(lines.lines.size(), 0);
  for (size_t r = 0; r < roots; ++r) {
    ASSERT_LE(lines.rootFirstLine[r], lines.rootFirstLine[r + 1]);
    for (uint32_t i = lines.rootFirstLine[r]; i < lines.rootFirstLine[r + 1]; ++i) {
      const uint32_t l = lines.linesByRoot[i];
      ++listed.at(l);
      const SeamLines::Line& line = lines.lines[l];
      EXPECT_EQ(lines.rootSides[line.firstSide] / 4, r) << "line " << l;
      for (uint32_t s = line.firstSide; s < line.firstSide + line.sideCount; ++s) {
        EXPECT_GE(lines.rootSides[s] / 4, r) << "line " << l;
      }
    }
  }
  EXPECT_EQ(lines.rootFirstLine[roots], lines.lines.size());
  for (size_t l = 0; l < listed.size(); ++l) EXPECT_EQ(listed[l], 1) << "line " << l;
}

TEST(SeamLines, EveryLineListedOnceUnderTheRootOfItsFirstSide) {
  for (const char* shape : {"catmark_torus_creases0", "catmark_hole_test1", "catmark_nonquads", "catmark_fan"}) {
    expectLinesByTheirFirstRoot(shape);
  }
}

}  // namespace
}  // namespace tessera
