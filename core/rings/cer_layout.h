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

#include "core/base/host_device.h"

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
  // The walk above moves at most four sectors: wrapping by steps avoids two divisions per point.
  while (sector < 0) sector += shape.sectors;
  while (sector >= shape.sectors) sector -= shape.sectors;
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

// ---------------------------------------------------------------------------------------------
// The paper's recovering and locating operators (§4.1.2, §4.2), by index arithmetic alone.
// Interior vertices j: 0 = EV, 1 + 2i = e_i, 2 + 2i = d_i (an open ring adds e_n as 2n + 1).
// Faces f = 4i + k: k = 0 the inner quad [0,1]², 1 [1,2]×[0,1], 2 [1,2]², 3 [0,1]×[1,2].
// Interior edges e = 6i + k: 0 EV–e_i, 1 e_i–a_i (the spoke), 2 e_i–d_i, 3 d_i–(1,2),
// 4 e_{i+1}–d_i, 5 d_i–(2,1) (an open ring adds its closing spoke's two edges as 6n, 6n + 1).
// Results are packed four to a word: 8-bit indices while the refined set has at most 256 points
// (valence <= 21), 16-bit beyond.

struct PackedIndices {
  uint64_t bits = 0;
  int width = 8;
  TESSERA_HD int operator[](int k) const { return int((bits >> (k * width)) & ((1u << width) - 1)); }
};

TESSERA_HD int indexBits(const RingShape& shape) { return shape.refinedPointCount() <= 256 ? 8 : 16; }

TESSERA_HD PackedIndices pack(const RingShape& shape, int a, int b, int c = 0, int d = 0) {
  PackedIndices p;
  p.width = indexBits(shape);
  p.bits = uint64_t(a) | uint64_t(b) << p.width | uint64_t(c) << (2 * p.width) |
           uint64_t(d) << (3 * p.width);
  return p;
}

TESSERA_HD int nextSectorOf(const RingShape& shape, int i) {
  return shape.open ? i + 1 : (i + 1) % shape.sectors;
}
TESSERA_HD int prevSectorOf(const RingShape& shape, int i) {
  return shape.open ? i - 1 : (i + shape.sectors - 1) % shape.sectors;
}

// vertex_f: the four corners of face f, counter-clockwise, as ring indices.
TESSERA_HD PackedIndices vertexF(const RingShape& shape, int f) {
  int i = f / 4, next = nextSectorOf(shape, i);
  int e = ringIndex(i, kE), d = ringIndex(i, kD), eNext = ringIndex(next, kE);
  switch (f % 4) {
    case 0: return pack(shape, 0, e, d, eNext);
    case 1: return pack(shape, e, ringIndex(i, kA), ringIndex(i, kD21), d);
    case 2: return pack(shape, d, ringIndex(i, kD21), ringIndex(i, kD22), ringIndex(i, kD12));
    default: return pack(shape, eNext, d, ringIndex(i, kD12), ringIndex(next, kA));
  }
}

// vertex_e: the two ends of interior edge e.
TESSERA_HD PackedIndices vertexE(const RingShape& shape, int e) {
  int i = e / 6, next = nextSectorOf(shape, i);
  int d = ringIndex(i, kD);
  switch (e % 6) {
    case 0: return pack(shape, 0, ringIndex(i, kE));
    case 1: return pack(shape, ringIndex(i, kE), ringIndex(i, kA));
    case 2: return pack(shape, ringIndex(i, kE), d);
    case 3: return pack(shape, d, ringIndex(i, kD12));
    case 4: return pack(shape, ringIndex(next, kE), d);
    default: return pack(shape, d, ringIndex(i, kD21));
  }
}

// face_e: the two faces of interior edge e (spoke edges take the previous sector's face second).
TESSERA_HD PackedIndices faceE(const RingShape& shape, int e) {
  int i = e / 6, prev = prevSectorOf(shape, i);
  switch (e % 6) {
    case 0: return pack(shape, 4 * i, 4 * prev);
    case 1: return pack(shape, 4 * i + 1, 4 * prev + 3);
    case 2: return pack(shape, 4 * i, 4 * i + 1);
    case 3: return pack(shape, 4 * i + 3, 4 * i + 2);
    case 4: return pack(shape, 4 * i, 4 * i + 3);
    default: return pack(shape, 4 * i + 1, 4 * i + 2);
  }
}

// vertex_v: the four neighbours of a regular interior vertex (e_i: EV and a_i first, along the
// spoke; then d_i, d_{i-1}).
TESSERA_HD PackedIndices vertexV(const RingShape& shape, int j) {
  int i = (j - 1) / 2;
  if (j % 2 == 1) {
    return pack(shape, 0, ringIndex(i, kA), ringIndex(i, kD), ringIndex(prevSectorOf(shape, i), kD));
  }
  return pack(shape, ringIndex(i, kE), ringIndex(nextSectorOf(shape, i), kE), ringIndex(i, kD21),
              ringIndex(i, kD12));
}

// face_v: the four faces around a regular interior vertex.
TESSERA_HD PackedIndices faceV(const RingShape& shape, int j) {
  int i = (j - 1) / 2;
  if (j % 2 == 1) {
    int prev = prevSectorOf(shape, i);
    return pack(shape, 4 * i, 4 * i + 1, 4 * prev, 4 * prev + 3);
  }
  return pack(shape, 4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3);
}

// The ring index of interior vertex j.
TESSERA_HD int ringIndexOfVertex(int j) {
  if (j == 0) return 0;
  return ringIndex((j - 1) / 2, j % 2 == 1 ? kE : kD);
}

// locate_f, locate_e, locate_v: where a face, edge or vertex point goes in the refined set.
TESSERA_HD int locateF(const RingShape& shape, int f) {
  int i = f / 4;
  switch (f % 4) {
    case 0: return ringIndex(i, kD);
    case 1: return extraIndex(shape, i, kX31);
    case 2: return extraIndex(shape, i, kX33);
    default: return extraIndex(shape, i, kX13);
  }
}

TESSERA_HD int locateE(const RingShape& shape, int e) {
  int i = e / 6;
  switch (e % 6) {
    case 0: return ringIndex(i, kE);
    case 1: return extraIndex(shape, i, kX30);
    case 2: return ringIndex(i, kD21);
    case 3: return extraIndex(shape, i, kX23);
    case 4: return ringIndex(i, kD12);
    default: return extraIndex(shape, i, kX32);
  }
}

TESSERA_HD int locateV(const RingShape&, int j) {
  if (j == 0) return 0;
  int i = (j - 1) / 2;
  return ringIndex(i, j % 2 == 1 ? kA : kD22);
}

}  // namespace tessera::cer
