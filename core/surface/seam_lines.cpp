#include "core/surface/seam_lines.h"

#include <algorithm>

namespace tessera {

namespace {

// How a root corner splits its normal: a base vertex by its wedge, the middle of an infinitely
// sharp edge by the face, an n-gon centre never.
int cornerQualifierOf(const SeamTopology& seams, int face, int sub, int c) {
  if (sub < 0) return seams.wedge(face, c);
  switch (c) {
    case 0: return seams.wedge(face, sub);
    case 1: return seams.sharp(seams.corner(face, sub), seams.corner(face, sub + 1)) ? face : -1;
    case 2: return -1;
    default: return seams.sharp(seams.corner(face, sub - 1), seams.corner(face, sub)) ? face : -1;
  }
}

}  // namespace

SeamLines::SeamLines(const SurfaceTree& tree, const SeamTopology& seams, int vertexCount) {
  const size_t sides = 4 * tree.roots.size();
  lineOf.assign(sides, UINT32_MAX);
  sideLine.resize(sides);
  cornerQualifier.assign(sides, -1);
  std::vector<std::pair<SeamLine, uint32_t>> keyed;
  for (uint32_t r = 0; r < tree.roots.size(); ++r) {
    const SurfaceRoot& root = tree.roots[r];
    if (root.node == kNoNode) continue;
    for (int k = 0; k < 4; ++k) {
      sideLine[4 * r + k] = rootSideLine(seams, root.baseFace, root.subFace, k);
      cornerQualifier[4 * r + k] = cornerQualifierOf(seams, root.baseFace, root.subFace, k);
      keyed.push_back({sideLine[4 * r + k].line, 4 * r + k});
    }
  }
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second < b.second);
  });
  const uint32_t faceCount = uint32_t(seams.faceSizes.size());
  std::vector<SeamLine> keys;
  for (size_t i = 0; i < keyed.size();) {
    size_t j = i;
    Line line;
    line.firstSide = uint32_t(rootSides.size());
    while (j < keyed.size() && keyed[j].first == keyed[i].first) {
      const uint32_t side = keyed[j++].second;
      lineOf[side] = uint32_t(lines.size());
      rootSides.push_back(side);
      line.sharp = sideLine[side].sharp;
      if (sideLine[side].halves == 2) line.node[1] = uint32_t(vertexCount) + faceCount + uint32_t(lines.size());
    }
    line.sideCount = uint32_t(rootSides.size()) - line.firstSide;
    const SeamLine& key = keyed[i].first;
    if (key.kind == SeamLine::kEdge) line.node[0] = uint32_t(key.a), line.node[2] = uint32_t(key.b);
    keys.push_back(key);
    lines.push_back(line);
    i = j;
  }
  // A spoke runs from the middle of its edge (that edge line's middle node) to the centre.
  for (size_t l = 0; l < lines.size(); ++l) {
    if (keys[l].kind != SeamLine::kSpoke) continue;
    const int face = keys[l].a, k = keys[l].b;
    const int a = seams.corner(face, k), b = seams.corner(face, k + 1);
    const SeamLine edge{SeamLine::kEdge, std::min(a, b), std::max(a, b)};
    const size_t e = std::lower_bound(keys.begin(), keys.end(), edge) - keys.begin();
    lines[l].node[0] = lines[e].node[1];
    lines[l].node[2] = uint32_t(vertexCount) + uint32_t(face);
  }
  nodeCount = uint32_t(vertexCount) + faceCount + uint32_t(lines.size());
  rootFirstLine.assign(tree.roots.size() + 1, 0);
  for (const Line& line : lines) ++rootFirstLine[rootSides[line.firstSide] / 4 + 1];
  for (size_t r = 0; r < tree.roots.size(); ++r) rootFirstLine[r + 1] += rootFirstLine[r];
  linesByRoot.resize(lines.size());
  std::vector<uint32_t> next(rootFirstLine.begin(), rootFirstLine.end() - 1);
  for (uint32_t l = 0; l < lines.size(); ++l) linesByRoot[next[rootSides[lines[l].firstSide] / 4]++] = l;
}

size_t SeamLines::bytes() const {
  return lines.size() * sizeof(Line) + rootSides.size() * sizeof(uint32_t) + lineOf.size() * sizeof(uint32_t) +
         sideLine.size() * sizeof(SideLine) + cornerQualifier.size() * sizeof(int) +
         (linesByRoot.size() + rootFirstLine.size()) * sizeof(uint32_t);
}

}  // namespace tessera
