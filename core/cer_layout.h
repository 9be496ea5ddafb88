// Connectivity-elided representation (CER) of an extraordinary ring (paper §4.1, MATH.md §1).
//
// A ring around an extraordinary vertex (EV) of valence n is stored as a plain array of
// 6n+1 points; adjacency and output offsets are recovered from indices alone. Each sector i
// (the face F_i around the EV) has an integer lattice frame: EV = (0,0), e_i = (1,0),
// d_i = (1,1), e_{i+1} = (0,1). Sector i owns the six points (1,0),(2,0),(1,1),(2,1),(2,2),(1,2),
// stored at 1 + 6i + slot. One refinement step produces the 12n+1 points of the doubled lattice:
// the next ring first (same layout), then per sector the six points (3,0),(3,1),(3,2),(3,3),
// (1,3),(2,3) that only the emitted B-spline patches need.
//
// An open ring (EV on a boundary, k faces) has no sector wrapping around; it carries the points
// (1,0),(2,0) of a closing spoke k after its 6k sector points (and (3,0) after the extras).
//
// Everything here is index arithmetic shared by the CPU kernels and CUDA.
#pragma once

#include <cstdint>

#include "core/host_device.h"

namespace tessera::cer {

inline constexpr int kSlotsPerSector = 6;

// Ring slots (lattice points a sector owns at ring level).
enum RingSlot : int { kE = 0, kA = 1, kD = 2, kD21 = 3, kD22 = 4, kD12 = 5 };
// Extra slots of the refined set: (3,0),(3,1),(3,2),(3,3),(1,3),(2,3).
enum ExtraSlot : int { kX30 = 0, kX31 = 1, kX32 = 2, kX33 = 3, kX13 = 4, kX23 = 5 };

struct RingShape {
  int sectors = 0;    // n: faces around the EV
  bool open = false;  // EV on a boundary: spokes 0 and n are boundary edges

  TESSERA_HD int ringPointCount() const { return 1 + kSlotsPerSector * sectors + (open ? 2 : 0); }
  // 12n+1 for a closed ring; an open ring adds the closing spoke's (1,0),(2,0),(3,0).
  TESSERA_HD int refinedPointCount() const {
    return ringPointCount() + kSlotsPerSector * sectors + (open ? 1 : 0);
  }
  // Number of spokes (lines from the EV along sector x-axes): n closed, n+1 open.
  TESSERA_HD int spokeCount() const { return sectors + (open ? 1 : 0); }
};

TESSERA_HD int ringIndex(int sector, int slot) { return 1 + kSlotsPerSector * sector + slot; }

// Closing spoke of an open ring: its (1,0) and (2,0) are stored like a sector's first two slots.
TESSERA_HD int extraIndex(const RingShape& shape, int sector, int slot) {
  return shape.ringPointCount() + kSlotsPerSector * sector + slot;
}

// Maps a lattice point (x, y) of sector i with 0 <= x, y <= 3 to the canonical sector and
// non-negative coordinates, following MATH.md §1: y < 0 -> (i-1, -y, x); x < 0 -> (i+1, y, -x);
// x = 0 < y -> (i+1, y, 0). Returns false when the point lies past an open ring's boundary.
TESSERA_HD bool canonicalize(const RingShape& shape, int& sector, int& x, int& y) {
  for (int guard = 0; guard < 4; ++guard) {
    if (y < 0) {
      int t = x;
      x = -y, y = t, sector -= 1;
    } else if (x < 0) {
      int t = y;
      y = -x, x = t, sector += 1;
    } else if (x == 0 && y > 0) {
      x = y, y = 0, sector += 1;
    } else {
      break;
    }
  }
  if (x == 0 && y == 0) return true;
  if (shape.open) return sector >= 0 && (sector < shape.sectors || (sector == shape.sectors && y == 0));
  sector = ((sector % shape.sectors) + shape.sectors) % shape.sectors;
  return true;
}

// Index of a canonical point of the refined (12n+1) set, coordinates in 0..3.
TESSERA_HD int refinedIndexCanonical(const RingShape& shape, int sector, int x, int y) {
  if (x == 0 && y == 0) return 0;
  if (x <= 2 && y <= 2) {
    // (1,0)->kE (2,0)->kA (1,1)->kD (2,1)->kD21 (2,2)->kD22 (1,2)->kD12
    int slot = y == 0 ? x - 1 : (y == 1 ? (x == 1 ? kD : kD21) : (x == 2 ? kD22 : kD12));
    return ringIndex(sector, slot);
  }
  int slot = x == 3 ? y : (x == 1 ? kX13 : kX23);  // (3,y) -> y, (1,3) -> 4, (2,3) -> 5
  return extraIndex(shape, sector, slot);
}

// Index of any lattice point of sector i's refined set, or -1 past an open boundary.
TESSERA_HD int refinedIndex(const RingShape& shape, int sector, int x, int y) {
  if (!canonicalize(shape, sector, x, y)) return -1;
  return refinedIndexCanonical(shape, sector, x, y);
}

}  // namespace tessera::cer
