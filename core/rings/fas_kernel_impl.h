// The body of the block kernel declared in fas_kernel.h, included by fas_kernel_avx2.cpp and
// fas_kernel_avx512.cpp only. Everything here has internal linkage (anonymous namespace): the two
// translation units are compiled for different instruction sets, and an inline function with
// external linkage would let the linker keep one copy for both, AVX-512 code on AVX2-only CPUs.
// For the same reason the kernel uses no TBB and no std algorithms, only plain pointer loops.
//
// Every point is computed from the same operands with the same operations in the same order as
// fas_rules.h (the scalar per-point path), so both builds are bit-identical to it
// (tests/fas_test.cpp). Intrinsics rather than auto-vectorised loops: each result vector is
// stored twice from the register, once into the ring buffer and once to the output.
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "core/rings/fas.h"
#include "core/rings/fas_kernel.h"

namespace tessera::fas_kernel {
namespace {

#if defined(__AVX512F__)
using Vec = __m512;
constexpr int kVectorFloats = 16;
inline Vec load(const float* p) {
  return _mm512_loadu_ps(p);
}
inline Vec broadcast(float s) {
  return _mm512_set1_ps(s);
}
inline Vec add(Vec a, Vec b) {
  return _mm512_add_ps(a, b);
}
inline Vec mul(Vec a, Vec b) {
  return _mm512_mul_ps(a, b);
}
inline void storeAligned(float* p, Vec v) {
  _mm512_store_ps(p, v);
}
inline void storeUnaligned(float* p, Vec v) {
  _mm512_storeu_ps(p, v);
}
inline void stream(float* p, Vec v) {
  _mm512_stream_ps(p, v);
}
#else
using Vec = __m256;
constexpr int kVectorFloats = 8;
inline Vec load(const float* p) {
  return _mm256_loadu_ps(p);
}
inline Vec broadcast(float s) {
  return _mm256_set1_ps(s);
}
inline Vec add(Vec a, Vec b) {
  return _mm256_add_ps(a, b);
}
inline Vec mul(Vec a, Vec b) {
  return _mm256_mul_ps(a, b);
}
inline void storeAligned(float* p, Vec v) {
  _mm256_store_ps(p, v);
}
inline void storeUnaligned(float* p, Vec v) {
  _mm256_storeu_ps(p, v);
}
inline void stream(float* p, Vec v) {
  _mm256_stream_ps(p, v);
}
#endif

constexpr int W = kFasBlockFloats;
static_assert(W % kVectorFloats == 0, "a point of a block is whole vectors");

// Where one step's results go: the refined set in the ring buffer (the next ring, and the face
// points the edge and vertex rules read back) and the level's slice of the output, which has
// the same layout. The output is written once and not read back here, so an aligned one is
// streamed past the cache; with 16 lanes a point is whole cache lines, so the order in which
// points are written costs the write-combining buffers nothing.
template <bool kStreaming>
struct Destination {
  float* refined;
  float* output;

  void put(uint32_t offset, int k, Vec v) const {
    storeAligned(refined + offset + k, v);
    if constexpr (kStreaming) {
      stream(output + offset + k, v);
    } else {
      storeUnaligned(output + offset + k, v);
    }
  }
};

// Face point, or smooth edge point with two face points as c and d: ((a + b) + (c + d)) / 4.
template <class Out>
inline void average4(const Out& out, uint32_t at, const float* a, const float* b, const float* c,
                     const float* d) {
  const Vec quarter = broadcast(0.25f);
  for (int k = 0; k < W; k += kVectorFloats) {
    Vec sum = add(add(load(a + k), load(b + k)), add(load(c + k), load(d + k)));
    out.put(at, k, mul(quarter, sum));
  }
}

template <class Out>
inline void midpoint(const Out& out, uint32_t at, const float* a, const float* b) {
  const Vec half = broadcast(0.5f);
  for (int k = 0; k < W; k += kVectorFloats)
    out.put(at, k, mul(half, add(load(a + k), load(b + k))));
}

// Crease vertex rule: 3/4 v + 1/8 (a + b).
template <class Out>
inline void creaseVertex(const Out& out, uint32_t at, const float* v, const float* a,
                         const float* b) {
  const Vec threeQuarters = broadcast(0.75f), eighth = broadcast(0.125f);
  for (int k = 0; k < W; k += kVectorFloats) {
    Vec ends = add(load(a + k), load(b + k));
    out.put(at, k, add(mul(threeQuarters, load(v + k)), mul(eighth, ends)));
  }
}

// Smooth valence-4 vertex rule: v/2 + ((n0 + n1) + (n2 + n3) + (f0 + f1) + (f2 + f3)) / 16.
template <class Out>
inline void regularVertex(const Out& out, uint32_t at, const float* in, const float* faces,
                          const StepProgram::SmoothVertex& s) {
  const Vec half = broadcast(0.5f), sixteenth = broadcast(0.0625f);
  for (int k = 0; k < W; k += kVectorFloats) {
    Vec edges = add(add(load(in + s.n[0] + k), load(in + s.n[1] + k)),
                    add(load(in + s.n[2] + k), load(in + s.n[3] + k)));
    Vec facePoints = add(add(load(faces + s.f[0] + k), load(faces + s.f[1] + k)),
                         add(load(faces + s.f[2] + k), load(faces + s.f[3] + k)));
    out.put(at, k, add(mul(half, load(in + s.v + k)), mul(sixteenth, add(edges, facePoints))));
  }
}

// The EV: every lane adds the smooth rule's terms in sector order, as
// refineExtraordinaryVertex does.
template <class Out>
inline void extraordinaryVertex(const StepProgram& p, const Out& out, const float* in) {
  const float* faces = out.refined;
  if (p.evRule == EvRule::kCorner) {
    for (int k = 0; k < W; k += kVectorFloats) out.put(0, k, load(in + k));
  } else if (p.evRule == EvRule::kCrease) {
    creaseVertex(out, 0, in, in + p.evCreaseA, in + p.evCreaseB);
  } else {
    const Vec self = broadcast(p.evSelfWeight), ring = broadcast(p.evRingWeight);
    const StepProgram::EvTerm* terms = p.evTerms.data();
    const size_t count = p.evTerms.size();
    for (int k = 0; k < W; k += kVectorFloats) {
      Vec sum = broadcast(0.0f);
      for (size_t i = 0; i < count; ++i) {
        sum = add(sum, add(load(in + terms[i].edge + k), load(faces + terms[i].face + k)));
      }
      out.put(0, k, add(mul(self, load(in + k)), mul(ring, sum)));
    }
  }
}

// One step for one block: faces first (the edge, vertex and EV rules read them back).
template <class Out>
inline void refineStep(const StepProgram& p, const float* in, const Out& out) {
  const float* faces = out.refined;
  for (const StepProgram::Face& s : p.faces) {
    average4(out, s.out, in + s.a, in + s.b, in + s.c, in + s.d);
  }
  for (const StepProgram::SmoothEdge& s : p.smoothEdges) {
    average4(out, s.out, in + s.v0, in + s.v1, faces + s.f0, faces + s.f1);
  }
  for (const StepProgram::SharpEdge& s : p.sharpEdges) midpoint(out, s.out, in + s.v0, in + s.v1);
  for (const StepProgram::SmoothVertex& s : p.smoothVertices)
    regularVertex(out, s.out, in, faces, s);
  for (const StepProgram::CreaseVertex& s : p.creaseVertices) {
    creaseVertex(out, s.out, in + s.v, in + s.n0, in + s.n1);
  }
  extraordinaryVertex(p, out, in);
}

template <bool kStreaming>
inline void refineBlocksTo(const BlockJob& job, int begin, int end) {
  for (int b = begin; b != end; ++b) {
    const float* ring = job.blocks + size_t(b) * job.ringFloats;
    float* out = job.output + size_t(b) * job.depth * job.refinedFloats;
    for (int level = 0; level < job.depth; ++level) {
      const Destination<kStreaming> destination{job.ringBuffer[level & 1],
                                                out + level * job.refinedFloats};
      refineStep(*job.program, ring, destination);
      ring = destination.refined;
    }
  }
}

// The fence makes this thread's streamed stores visible before the task reports completion.
inline void refineBlocks(const BlockJob& job, int begin, int end) {
  if (reinterpret_cast<uintptr_t>(job.output) % (4 * kVectorFloats) == 0) {
    refineBlocksTo<true>(job, begin, end);
    _mm_sfence();
  } else {
    refineBlocksTo<false>(job, begin, end);
  }
}

}  // namespace
}  // namespace tessera::fas_kernel
