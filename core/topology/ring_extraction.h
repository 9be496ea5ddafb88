// Gathers an extraordinary ring from OpenSubdiv's adaptive refinement in CER order and checks
// that the ring is one FAS supports: all non-EV ring vertices regular, creases only along spokes
// (straight, infinitely sharp), boundaries only as the first and last spoke.
#pragma once

#include <optional>
#include <vector>

#include <opensubdiv/far/topologyRefiner.h>

#include "core/base/vec3.h"
#include "core/rings/cer_layout.h"

namespace tessera {

namespace Far = OpenSubdiv::Far;

struct RefinedMesh {
  const Far::TopologyRefiner& refiner;
  const std::vector<Vec3d>& positions;  // all levels concatenated
  const std::vector<int>& levelOffsets;
  Vec3d position(int level, Far::Index v) const { return positions[levelOffsets[level] + v]; }
};

struct GatheredRing {
  cer::RingShape shape;
  std::vector<Vec3d> points;  // CER ring order
  std::vector<uint8_t> sharpSpokes;
  bool cornerEv = false;
  std::vector<Far::Index> sectorFaces;  // faces around the EV at the ring's level
  std::vector<int> sectorRotations;     // local corner of the EV in each face
};

// The ring around `ev` at `level`. Far's sparse levels can lack the outer part of a ring (next
// to a hole, say); then the ring is gathered one level up and refined one FAS step. Throws
// TesseraError (kUnsupported) when the neighbourhood is not a supported ring.
GatheredRing extractRing(const RefinedMesh& mesh, int level, Far::Index ev);

}  // namespace tessera
