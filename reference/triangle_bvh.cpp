#include "reference/triangle_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

namespace tessera::testing {

namespace {

constexpr uint32_t kParallelBuild = 1
                                    << 16;  // below this many triangles a subtree is built serially

// Nodes of the subtree over n triangles: median splits make it a function of n alone, so every
// subtree's place in the node array is known before it is built (the left child follows its
// parent, the right child follows the left subtree), and subtrees can be built concurrently.
uint32_t subtreeNodes(uint32_t n, uint32_t leafSize) {
  static thread_local std::map<std::pair<uint32_t, uint32_t>, uint32_t> memo;
  if (n <= leafSize) return 1;
  auto found = memo.find({n, leafSize});
  if (found != memo.end()) return found->second;
  const uint32_t count = 1 + subtreeNodes(n / 2, leafSize) + subtreeNodes(n - n / 2, leafSize);
  memo[{n, leafSize}] = count;
  return count;
}

double boxDistanceSquared(const float lo[3], const float hi[3], const Vec3d& p) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double below = double(lo[k]) - p[k], above = p[k] - double(hi[k]);
    const double outside = std::max({below, above, 0.0});
    d2 += outside * outside;
  }
  return d2;
}

}  // namespace

void TriangleBvh::grow(Node& box, const Vec3& x) {
  for (int k = 0; k < 3; ++k) {
    box.lo[k] = std::min(box.lo[k], x[k]);
    box.hi[k] = std::max(box.hi[k], x[k]);
  }
}

Vec3d closestPointOnTriangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3d bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3d cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const double denominator = va + vb + vc;
  // A degenerate triangle whose corners lie on a line has no interior region; a corner will do.
  if (denominator <= 0) return a;
  return a + ab * (vb / denominator) + ac * (vc / denominator);
}

TriangleBvh::TriangleBvh(std::span<const Vec3> positions, std::span<const uint32_t> indices)
    : positions_(positions), indices_(indices) {
  const uint32_t n = uint32_t(indices.size() / 3);
  if (n == 0) return;
  std::vector<Vec3> centroids(n);
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t t) {
    centroids[t] = (corner(t, 0) + corner(t, 1) + corner(t, 2)) * (1.0f / 3.0f);
  });
  order_.resize(n);
  for (uint32_t t = 0; t < n; ++t) order_[t] = t;
  nodes_.resize(subtreeNodes(n, kLeafSize));
  build(0, 0, n, centroids);
}

// Splits at the median centroid along the longest axis of the centroids' box; boxes are formed
// bottom-up (a leaf from its corners, a parent from its children), so each level reads the
// triangles once, for the split.
void TriangleBvh::build(uint32_t node, uint32_t begin, uint32_t end,
                        const std::vector<Vec3>& centroids) {
  Node& self = nodes_[node];
  std::fill(self.lo, self.lo + 3, std::numeric_limits<float>::max());
  std::fill(self.hi, self.hi + 3, std::numeric_limits<float>::lowest());
  const uint32_t n = end - begin;
  if (n <= kLeafSize) {
    for (uint32_t i = begin; i < end; ++i) {
      for (int c = 0; c < 3; ++c) grow(self, corner(order_[i], c));
    }
    self.rightOrFirst = begin;
    self.count = n;
    return;
  }
  Node centroidBox;
  std::fill(centroidBox.lo, centroidBox.lo + 3, std::numeric_limits<float>::max());
  std::fill(centroidBox.hi, centroidBox.hi + 3, std::numeric_limits<float>::lowest());
  for (uint32_t i = begin; i < end; ++i) grow(centroidBox, centroids[order_[i]]);
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    const float extent = centroidBox.hi[k] - centroidBox.lo[k];
    if (extent > centroidBox.hi[axis] - centroidBox.lo[axis]) axis = k;
  }
  const uint32_t middle = begin + n / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                   [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  const uint32_t left = node + 1, right = left + subtreeNodes(n / 2, kLeafSize);
  self.rightOrFirst = right;
  self.count = 0;
  if (n >= kParallelBuild) {
    tbb::parallel_invoke([&] { build(left, begin, middle, centroids); },
                         [&] { build(right, middle, end, centroids); });
  } else {
    build(left, begin, middle, centroids);
    build(right, middle, end, centroids);
  }
  for (const uint32_t child : {left, right}) {
    grow(self, Vec3(nodes_[child].lo[0], nodes_[child].lo[1], nodes_[child].lo[2]));
    grow(self, Vec3(nodes_[child].hi[0], nodes_[child].hi[1], nodes_[child].hi[2]));
  }
}

TriangleBvh::Nearest TriangleBvh::nearest(const Vec3d& query) const {
  Nearest best;
  double bestD2 = std::numeric_limits<double>::infinity();
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistanceSquared(node.lo, node.hi, query) >= bestD2) continue;
    if (node.count > 0) {
      for (uint32_t i = node.rightOrFirst; i < node.rightOrFirst + node.count; ++i) {
        const uint32_t t = order_[i];
        const Vec3d point = closestPointOnTriangle(query, Vec3d(corner(t, 0)), Vec3d(corner(t, 1)),
                                                   Vec3d(corner(t, 2)));
        const Vec3d offset = point - query;
        const double d2 = dot(offset, offset);
        if (d2 < bestD2) bestD2 = d2, best.triangle = t, best.point = point;
      }
      continue;
    }
    // Nearer child last so that it is searched first.
    const uint32_t left = uint32_t(&node - nodes_.data()) + 1, right = node.rightOrFirst;
    const double dLeft = boxDistanceSquared(nodes_[left].lo, nodes_[left].hi, query);
    const double dRight = boxDistanceSquared(nodes_[right].lo, nodes_[right].hi, query);
    if (dLeft < dRight) {
      if (dRight < bestD2) stack[top++] = right;
      if (dLeft < bestD2) stack[top++] = left;
    } else {
      if (dLeft < bestD2) stack[top++] = left;
      if (dRight < bestD2) stack[top++] = right;
    }
  }
  best.distance = std::sqrt(bestD2);
  return best;
}

}  // namespace tessera::testing
