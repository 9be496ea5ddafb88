// Gathers an extraordinary ring from OpenSubdiv's adaptive refinement in CER order and checks
// that the ring is one FAS supports: all non-EV ring vertices regular, creases only along spokes
// (straight, infinitely sharp), boundaries only as the first and last spoke. Far's sparse levels
// can lack the outer part of a ring; then it is gathered one level up and refined one FAS step.
#pragma once

#include <vector>

#include <opensubdiv/far/topologyRefiner.h>

#include "core/base/vec3.h"
#include "core/rings/cer_layout.h"

namespace tessera {

namespace Far = OpenSubdiv::Far;

// Every refined vertex of a refiner's levels, levels concatenated (Far's numbering with the base
// level first), as refinedPositions (far_topology.h) lays out their positions.
struct RefinedLevels {
  const Far::TopologyRefiner& refiner;
  const std::vector<int>& levelOffsets;
  int index(int level, Far::Index v) const { return levelOffsets[level] + v; }
};

// Which refined vertices make the ring around an EV, from the topology alone: an edit that moves
// only positions keeps it (core/topology/patch_topology.h).
struct RingLayout {
  cer::RingShape shape;
  std::vector<int> points;  // CER ring order, each a refined vertex (RefinedLevels::index)
  std::vector<uint8_t> sharpSpokes;
  bool cornerEv = false;
  // Gathered one level up, where Far's sparse level lacks the ring's outer part (next to a hole,
  // say): its points are those one FAS step refines.
  bool refinedOnce = false;
  std::vector<Far::Index> sectorFaces;  // faces around the EV at the ring's level
  std::vector<int> sectorRotations;     // local corner of the EV in each face
};

// The ring around `ev` at `level`. Throws TesseraError (kUnsupported) when the neighbourhood is
// not a supported ring.
RingLayout layoutRing(const RefinedLevels& levels, int level, Far::Index ev);

// The ring's points, CER order, from every refined vertex's position (levels concatenated).
std::vector<Vec3d> ringPoints(const RingLayout& ring, const std::vector<Vec3d>& refinedPositions);

}  // namespace tessera
