// The depth tables are a bound: the innermost Bézier approximation after m FAS steps never
// deviates from OpenSubdiv's exact limit surface by more than c_m · (ring radius), on random
// rings and on every ring of the real models; and the checked-in tables regenerate exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "core/bounds/depth_bound.h"
#include "core/bounds/depth_tables.h"
#include "core/math/bicubic.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/rings/fas.h"
#include "core/rings/innermost_patch.h"
#include "reference/bfr_reference.h"
#include "reference/models.h"
#include "reference/ring_meshes.h"

namespace tessera {
namespace {

TEST(DepthBound, CheckedInTablesRegenerate) {
  for (int n : {3, 5, 7, 12}) {
    cer::RingShape shape{n, false};
    RingRules rules = makeRingRules(shape, nullptr, false);
    std::vector<double> regenerated = computeDepthBound({shape, {}, false});
    const std::vector<double>* table = depthCoefficients(rules);
    ASSERT_NE(table, nullptr);
    for (size_t m = 0; m < regenerated.size(); ++m) EXPECT_DOUBLE_EQ((*table)[m], regenerated[m]) << n << " " << m;
  }
  for (int k : {1, 2, 3, 6}) {
    cer::RingShape shape{k, true};
    RingRules rules = makeRingRules(shape, nullptr, false);
    std::vector<double> regenerated = computeDepthBound({shape, {}, false});
    const std::vector<double>* table = depthCoefficients(rules);
    ASSERT_NE(table, nullptr);
    for (size_t m = 0; m < regenerated.size(); ++m) EXPECT_DOUBLE_EQ((*table)[m], regenerated[m]) << k << " " << m;
  }
}

// Rings with sharp spokes or a corner EV take the creased tables, by their kind's canonical
// rotation: every rotation of a kind finds the canonical rotation's coefficients, computed again
// here, and those are the rotation's own computed coefficients to rounding (one ring, its sectors
// numbered from another spoke): 10⁻¹² of c_m, or 10⁻¹⁵ of c_0 where c_m has decayed to the
// rounding of the model's sums (each c_m carries a headroom of 10⁻⁶ of itself for that).
TEST(DepthBound, CreasedTablesRegenerateForEveryRotation) {
  struct Kind {
    cer::RingShape shape;
    std::vector<uint8_t> spokes;
    bool cornerEv;
  };
  const Kind kinds[] = {
      {{5, false}, {0, 1, 0, 0, 1}, false},        // a crease through an EV of valence 5
      {{6, false}, {0, 0, 0, 1, 0, 0}, false},     // a dart
      {{4, false}, {1, 1, 0, 1}, false},           // three sharp spokes: a corner
      {{3, false}, {0, 0, 0}, true},               // a corner-tagged smooth EV
      {{3, true}, {1, 0, 1, 1}, false},            // an open ring with an inner sharp spoke
      {{8, false}, {1, 0, 0, 1, 0, 0, 0, 0}, false},
  };
  for (const Kind& kind : kinds) {
    const int spokes = kind.shape.spokeCount();
    for (int r = 0; r < (kind.shape.open ? 1 : spokes); ++r) {
      std::vector<uint8_t> rotated(spokes);
      for (int s = 0; s < spokes; ++s) rotated[s] = kind.spokes[(s + r) % spokes];
      const RingRules rules = makeRingRules(kind.shape, rotated.data(), kind.cornerEv);
      SCOPED_TRACE(ringKindKey(ringKindOf(rules)));
      const std::vector<double>* table = depthCoefficients(rules);
      ASSERT_NE(table, nullptr);
      const std::vector<double> canonical = computeDepthBound(canonicalRotation(ringKindOf(rules)));
      const std::vector<double> own = computeDepthBound(ringKindOf(rules));
      for (size_t m = 0; m < canonical.size(); ++m) {
        EXPECT_DOUBLE_EQ((*table)[m], canonical[m]) << m;
        EXPECT_NEAR(own[m], canonical[m], 1e-12 * canonical[m] + 1e-15 * canonical[0]) << m;
      }
    }
  }
}

TEST(DepthBound, MatchesTheRegularCaseAndDecays) {
  // Valence 4 is a B-spline: only the tail term of the bound remains.
  auto regular = computeDepthBound({{4, false}, {}, false}, 4);
  EXPECT_LT(regular[0], 1e-3);
  for (int n : {3, 5, 8}) {
    auto c = computeDepthBound({{n, false}, {}, false});
    for (size_t m = 1; m < c.size(); ++m) EXPECT_LT(c[m], c[m - 1]) << n;
  }
}

struct BoundCheck {
  double worstRatio = 0;  // measured / bound
  int rings = 0;
};

// Samples sector domains of the innermost quads after m steps against a reference surface.
template <typename Reference>
void checkRing(const RingRules& rules, const float* ring, Vec3d center, const PatchDomain* sectorDomains,
               const uint8_t* owned, Reference& reference, int maxDepth, BoundCheck& check) {
  // `ring` is relative to `center`, its EV's control point, as Tessera stores rings.
  const std::vector<double>* c = depthCoefficients(rules);
  double radius = 0;
  for (int p = 0; p < rules.shape.ringPointCount(); ++p) {
    radius = std::max(radius, length(Vec3d(Vec3(ring[3 * p], ring[3 * p + 1], ring[3 * p + 2]))));
  }
  std::vector<float> levels = refineRing(rules, ring, maxDepth);
  for (int m = 0; m <= maxDepth; ++m) {
    const float* q = m == 0 ? ring : levels.data() + size_t(m - 1) * rules.shape.refinedPointCount() * 3;
    double bound = c != nullptr ? (*c)[m] * radius : 0;
    auto fetch = [q](int index) { return Vec3d(q[3 * index], q[3 * index + 1], q[3 * index + 2]); };
    for (int i = 0; i < rules.shape.sectors; ++i) {
      if (!owned[i]) continue;
      Vec3d bezier[16];
      innermostBezier<Vec3d>(rules, i, fetch, bezier);
      PatchDomain inner = sectorDomains[i].restrict(0, 0, std::ldexp(1.0, -m));
      double worst = 0;
      for (int a = 0; a <= 8; ++a) {
        for (int b = 0; b <= 8; ++b) {
          Vec3d exact;
          ASSERT_TRUE(reference.evaluate(inner, a / 8.0, b / 8.0, exact));
          worst = std::max(worst, length(evaluateBezier(bezier, a / 8.0, b / 8.0).position + center - exact));
        }
      }
      if (c == nullptr) continue;
      EXPECT_LE(worst, bound + 1e-6 * radius) << "valence " << rules.shape.sectors << " depth " << m;
      if (bound > 1e-9) check.worstRatio = std::max(check.worstRatio, worst / bound);
    }
  }
  ++check.rings;
}

TEST(DepthBound, BoundsTheErrorOnRandomRings) {
  BoundCheck check;
  for (int n : {3, 5, 6, 8}) {
    for (uint32_t seed = 0; seed < 3; ++seed) {
      cer::RingShape shape{n, false};
      ControlMesh mesh = testing::makeRingMesh(shape, 500 + 10 * n + seed);
      testing::BfrReference reference(mesh);
      RingRules rules = makeRingRules(shape, nullptr, false);
      const Vec3 center = mesh.positions[0];
      std::vector<float> ring;
      for (const Vec3& p : mesh.positions) {
        Vec3 d = p - center;
        ring.insert(ring.end(), {d.x, d.y, d.z});
      }
      // Ring meshes: sector i's inner face is face 4i with the EV at its first corner.
      std::vector<PatchDomain> domains(n);
      for (int i = 0; i < n; ++i) domains[i].baseFace = 4 * i;
      std::vector<uint8_t> owned(n, 1);
      checkRing(rules, ring.data(), Vec3d(center), domains.data(), owned.data(), reference, 6, check);
    }
  }
  EXPECT_GT(check.rings, 0);
  EXPECT_LE(check.worstRatio, 1.0);
}

TEST(DepthBound, BoundsTheErrorOnEveryRingOfTheModels) {
  for (const std::string& path : testing::benchmarkCharacters()) {
    SCOPED_TRACE(path);
    ControlMesh mesh = readObjFile(path);
    PatchSet set = buildPatchSet(mesh);
    testing::BfrReference reference(mesh);
    BoundCheck check;
    for (size_t r = 0; r < set.rings.size(); ++r) {
      // Bfr is exact to Far level 10 (see patch_set_test.cpp).
      int depth = std::min(4, 10 - set.rings.levels[r]);
      checkRing(set.rings.rules(r), set.rings.ringPoints(r), Vec3d(set.rings.centers[r]),
                set.rings.sectorDomains.data() + set.rings.sectorOffsets[r],
                set.rings.sectorOwned.data() + set.rings.sectorOffsets[r], reference, depth, check);
    }
    EXPECT_EQ(check.rings, int(set.rings.size()));
    EXPECT_LE(check.worstRatio, 1.0);
    std::printf("%s: %d rings, worst measured/bound %.3f\n", testing::baseName(path).c_str(),
                check.rings, check.worstRatio);
  }
}

// The creased tables against OpenSubdiv on real rings: the shapes whose infinitely sharp creases
// run through extraordinary vertices (cubes, creases meeting at EVs, a crease ending in a dart).
TEST(DepthBound, BoundsTheErrorOnTheCreasedRingsOfTheShapes) {
  int creased = 0;
  for (const char* name : {"catmark_cubes_infsharp", "catmark_inf_crease0", "catmark_inf_crease1"}) {
    SCOPED_TRACE(name);
    ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/" + name + ".obj");
    PatchSet set = buildPatchSet(mesh);
    testing::BfrReference reference(mesh);
    BoundCheck check;
    for (size_t r = 0; r < set.rings.size(); ++r) {
      const RingRules rules = set.rings.rules(r);
      bool sharp = rules.evRule == EvRule::kCorner;
      for (int s = 0; s < rules.shape.spokeCount(); ++s) sharp |= !rules.shape.open && rules.spokeSharp(s);
      if (!sharp) continue;
      ++creased;
      const int depth = std::min(4, 10 - set.rings.levels[r]);
      checkRing(rules, set.rings.ringPoints(r), Vec3d(set.rings.centers[r]),
                set.rings.sectorDomains.data() + set.rings.sectorOffsets[r],
                set.rings.sectorOwned.data() + set.rings.sectorOffsets[r], reference, depth, check);
    }
    EXPECT_LE(check.worstRatio, 1.0);
    std::printf("%s: %d creased rings, worst measured/bound %.3f\n", name, check.rings, check.worstRatio);
  }
  EXPECT_GT(creased, 10);
}

}  // namespace
}  // namespace tessera
