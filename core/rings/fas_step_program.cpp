#include "core/rings/fas_step_program.h"

namespace tessera {

namespace {

// Appends the records of the step in the order fas_rules.h computes the points.
class StepDecoder {
 public:
  StepDecoder(const RingRules& rules, int pointFloats, StepProgram& program)
      : rules_(rules),
        shape_(rules.shape),
        pointFloats_(uint32_t(pointFloats)),
        program_(program) {}

  void faces() {
    for (int f = 0; f < 4 * shape_.sectors; ++f) {
      cer::PackedIndices v = cer::vertexF(shape_, f);
      program_.faces.push_back(
          {at(cer::locateF(shape_, f)), at(v[0]), at(v[1]), at(v[2]), at(v[3])});
    }
  }

  void edge(int e, bool sharp) {
    cer::PackedIndices v = cer::vertexE(shape_, e);
    const uint32_t out = at(cer::locateE(shape_, e));
    if (sharp) {
      program_.sharpEdges.push_back({out, at(v[0]), at(v[1])});
      return;
    }
    cer::PackedIndices f = cer::faceE(shape_, e);
    program_.smoothEdges.push_back({out, at(v[0]), at(v[1]), face(f[0]), face(f[1])});
  }

  void vertex(int j, bool sharp) {
    cer::PackedIndices n = cer::vertexV(shape_, j);
    const uint32_t out = at(cer::locateV(shape_, j)), v = at(cer::ringIndexOfVertex(j));
    if (sharp) {
      program_.creaseVertices.push_back({out, v, at(n[0]), at(n[1])});
      return;
    }
    cer::PackedIndices f = cer::faceV(shape_, j);
    program_.smoothVertices.push_back({out,
                                       v,
                                       {at(n[0]), at(n[1]), at(n[2]), at(n[3])},
                                       {face(f[0]), face(f[1]), face(f[2]), face(f[3])}});
  }

  void extraordinaryVertex() {
    const int n = shape_.sectors;
    program_.evRule = rules_.evRule;
    program_.evCreaseA = at(cer::ringIndex(rules_.creaseSpokeA, cer::kE));
    program_.evCreaseB = at(cer::ringIndex(rules_.creaseSpokeB, cer::kE));
    // The weights exactly as refineExtraordinaryVertex computes them in float.
    program_.evSelfWeight = float(n - 2) / float(n);
    program_.evRingWeight = 1.0f / float(n * n);
    for (int i = 0; i < n; ++i) {
      program_.evTerms.push_back({at(cer::ringIndex(i, cer::kE)), at(cer::ringIndex(i, cer::kD))});
    }
  }

 private:
  uint32_t at(int point) const { return uint32_t(point) * pointFloats_; }
  uint32_t face(int f) const { return at(cer::locateF(shape_, f)); }

  const RingRules& rules_;
  const cer::RingShape& shape_;
  uint32_t pointFloats_;
  StepProgram& program_;
};

}  // namespace

StepProgram decodeStep(const RingRules& rules, int pointFloats) {
  StepProgram program;
  StepDecoder decoder(rules, pointFloats, program);
  decoder.faces();
  for (int j = 0; j < rules.shape.spokeCount(); ++j) {
    const bool sharp = rules.spokeSharp(j);
    decoder.edge(6 * j, sharp);
    decoder.edge(6 * j + 1, sharp);
    decoder.vertex(1 + 2 * j, sharp);
  }
  for (int i = 0; i < rules.shape.sectors; ++i) {
    for (int e = 6 * i + 2; e < 6 * i + 6; ++e) decoder.edge(e, false);
    decoder.vertex(2 + 2 * i, false);
  }
  decoder.extraordinaryVertex();
  return program;
}

}  // namespace tessera
