// The workload of the paper's Table 1 (§4.3): 100K extraordinary rings of one valence, refined
// to depth 4, 5 or 6, every level's 12n+1 refined points written to memory. The rings are a few
// dozen distinct jittered rings (reference/ring_meshes.h) tiled to the full count, so every
// ring is read from and written to main memory as in a real model while setup stays cheap.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/rings/cer_layout.h"

namespace tessera::bench {

inline constexpr int kTableRings = 100'000;  // Table 1: 100K rings per case
inline constexpr int kDistinctRings = 64;
inline constexpr uint32_t kFirstSeed = 1000;

// Bytes one case writes: every level's refined set of every ring, xyz floats.
size_t refinedBytes(const cer::RingShape& shape, int depth, int rings);

// The mesh of distinct ring k (all share the topology of ring 0).
ControlMesh distinctRingMesh(const cer::RingShape& shape, int k);

// kDistinctRings rings, xyz per CER point, ring after ring.
std::vector<float> distinctRings(const cer::RingShape& shape);

// `rings` rings laid out ring after ring; ring r is distinct ring r % kDistinctRings.
std::vector<float> tiledRings(const cer::RingShape& shape, const std::vector<float>& distinct,
                              int rings);

// One benchmark case's prepared state (buffers, tables). Google Benchmark calls a benchmark
// function several times while it settles the iteration count; the slot keeps the state of the
// case being measured and frees it as soon as another case asks, so at most one case's
// (up to ~1 GB) buffers are alive at a time.
struct CaseState {
  virtual ~CaseState() = default;
};

template <class State, class Make>
State& preparedCase(const std::string& key, Make make) {
  struct Slot {
    std::string key;
    std::unique_ptr<CaseState> state;
  };
  static Slot slot;
  if (slot.key != key || !slot.state) {
    slot.state.reset();  // free the previous case before allocating this one
    slot.key.clear();
    slot.state = make();
    slot.key = key;
  }
  return static_cast<State&>(*slot.state);
}

}  // namespace tessera::bench
