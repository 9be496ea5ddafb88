#include "core/surface/root_seams.h"

#include <algorithm>

namespace tessera {

namespace {

// A root side's span of its line: t at s = 0 and s = 1 (scale kLineScale).
void lineSpan(const SideLine& line, int64_t& t0, int64_t& t1) {
  const int64_t origin = line.origin ? kLineScale : 0;
  t0 = origin, t1 = origin + line.sign * (kLineScale / line.halves);
  if (t1 < t0) std::swap(t0, t1);
}

}  // namespace

RootSeams::RootSeams(const SurfaceTree& tree, const SeamTopology& seams) {
  struct Entry {
    SeamLine key;
    Span span;
  };
  std::vector<Entry> all;
  for (uint32_t r = 0; r < tree.roots.size(); ++r) {
    if (tree.roots[r].node == kNoNode) continue;
    for (int k = 0; k < 4; ++k) {
      Span span{r, uint8_t(k), 0, 0, rootSideLine(seams, tree.roots[r].baseFace, tree.roots[r].subFace, k)};
      lineSpan(span.line, span.t0, span.t1);
      all.push_back({span.line.line, span});
    }
  }
  std::stable_sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
  std::vector<std::vector<Span>> others(4 * tree.roots.size());
  for (size_t i = 0; i < all.size();) {
    size_t j = i;
    while (j < all.size() && all[j].key == all[i].key) ++j;
    for (size_t a = i; a < j; ++a) {
      for (size_t b = i; b < j; ++b) {
        if (a != b) others[4 * size_t(all[a].span.root) + all[a].span.side].push_back(all[b].span);
      }
    }
    i = j;
  }
  first.assign(1, 0);
  for (auto& list : others) {
    spans.insert(spans.end(), list.begin(), list.end());
    first.push_back(uint32_t(spans.size()));
  }
  // The root's own side, for mapping its coordinates: kept beside, one per root side.
  own.resize(4 * tree.roots.size());
  for (const Entry& e : all) own[4 * size_t(e.span.root) + e.span.side] = e.span;
}

}  // namespace tessera
