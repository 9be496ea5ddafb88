#include "gpu/cuda/warp_step_program.h"

namespace tessera::cuda {
namespace {

// Appends the records' words and returns the word offset where they start.
template <class Record>
size_t appendRecords(const std::vector<Record>& records, std::vector<uint32_t>& words) {
  static_assert(sizeof(Record) % sizeof(uint32_t) == 0 && alignof(Record) == alignof(uint32_t));
  const size_t first = words.size();
  const auto* begin = reinterpret_cast<const uint32_t*>(records.data());
  words.insert(words.end(), begin, begin + records.size() * (sizeof(Record) / sizeof(uint32_t)));
  return first;
}

template <class Record>
const Record* at(const uint32_t* base, size_t offset) {
  return reinterpret_cast<const Record*>(base + offset);
}

}  // namespace

WarpStepImage makeWarpStepImage(const RingRules& rules) {
  const StepProgram program = decodeStep(rules, 3);
  WarpStepImage image;
  image.faces = appendRecords(program.faces, image.words);
  image.smoothEdges = appendRecords(program.smoothEdges, image.words);
  image.sharpEdges = appendRecords(program.sharpEdges, image.words);
  image.smoothVertices = appendRecords(program.smoothVertices, image.words);
  image.creaseVertices = appendRecords(program.creaseVertices, image.words);
  image.evTerms = appendRecords(program.evTerms, image.words);
  WarpStepProgram& counts = image.counts;
  counts.faceCount = int(program.faces.size());
  counts.smoothEdgeCount = int(program.smoothEdges.size());
  counts.sharpEdgeCount = int(program.sharpEdges.size());
  counts.smoothVertexCount = int(program.smoothVertices.size());
  counts.creaseVertexCount = int(program.creaseVertices.size());
  counts.evTermCount = int(program.evTerms.size());
  counts.evRule = program.evRule;
  counts.evCreaseA = program.evCreaseA;
  counts.evCreaseB = program.evCreaseB;
  counts.evSelfWeight = program.evSelfWeight;
  counts.evRingWeight = program.evRingWeight;
  return image;
}

WarpStepProgram bindWarpStep(const WarpStepImage& image, const uint32_t* base) {
  WarpStepProgram program = image.counts;
  program.faces = at<StepProgram::Face>(base, image.faces);
  program.smoothEdges = at<StepProgram::SmoothEdge>(base, image.smoothEdges);
  program.sharpEdges = at<StepProgram::SharpEdge>(base, image.sharpEdges);
  program.smoothVertices = at<StepProgram::SmoothVertex>(base, image.smoothVertices);
  program.creaseVertices = at<StepProgram::CreaseVertex>(base, image.creaseVertices);
  program.evTerms = at<StepProgram::EvTerm>(base, image.evTerms);
  return program;
}

}  // namespace tessera::cuda
