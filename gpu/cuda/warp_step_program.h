// One CER step decoded for a ring shape (core/rings/fas_step_program.h's StepProgram, point offsets in
// floats of one xyz point) as the FAS kernel reads it: every record kind in one word array,
// uploaded once per batch, read by the lanes from global memory (a few KB, cached in L1).
//
// The kernel once called the recovering and locating operators of cer_layout.h for every point
// of every ring at every level (paper §4.1). Measured on an H200 (ncu, Table 1, n = 6): the
// kernel was bound by instruction issue (77 % of issue slots busy, 2,400 warp instructions per
// ring and level), mostly that index arithmetic, and only n of 32 lanes worked in two of its
// three phases. The operators depend on the shape alone, so they run once per batch here, and
// the lanes stride over the records of each kind.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/host_device.h"
#include "core/rings/fas_step_program.h"

namespace tessera::cuda {

struct WarpStepProgram {
  const StepProgram::Face* faces = nullptr;
  const StepProgram::SmoothEdge* smoothEdges = nullptr;
  const StepProgram::SharpEdge* sharpEdges = nullptr;
  const StepProgram::SmoothVertex* smoothVertices = nullptr;
  const StepProgram::CreaseVertex* creaseVertices = nullptr;
  const StepProgram::EvTerm* evTerms = nullptr;
  int faceCount = 0, smoothEdgeCount = 0, sharpEdgeCount = 0;
  int smoothVertexCount = 0, creaseVertexCount = 0, evTermCount = 0;
  EvRule evRule = EvRule::kSmooth;
  uint32_t evCreaseA = 0, evCreaseB = 0;     // kCrease: the two sharp spokes' e points
  float evSelfWeight = 0, evRingWeight = 0;  // kSmooth: (n-2)/n and 1/n²
};

// decodeStep(rules, 3) as one word array, and where each record kind starts in it.
struct WarpStepImage {
  std::vector<uint32_t> words;
  size_t faces = 0, smoothEdges = 0, sharpEdges = 0, smoothVertices = 0, creaseVertices = 0,
         evTerms = 0;
  WarpStepProgram counts;  // counts and EV fields; pointers null until bound
};
WarpStepImage makeWarpStepImage(const RingRules& rules);

// The program whose records are a copy of image.words at `base` (host or device memory).
WarpStepProgram bindWarpStep(const WarpStepImage& image, const uint32_t* base);

}  // namespace tessera::cuda
