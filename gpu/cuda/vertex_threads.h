// What each thread of the vertex kernel does (vertex_kernel.cu): one vertex of the adaptive
// tessellation put on the limit surface, with core/surface/surface_point.h's arithmetic, reading the
// surface tree from flat arrays. Host-device: tests run it on the CPU in the kernel's order and
// compare with the CPU engine (tests/cuda/vertex_simulation_test.cpp).
#pragma once

#include <cstdint>

#include "core/base/host_device.h"
#include "core/stitching/tile_stitching.h"
#include "core/surface/surface_point.h"

namespace tessera::cuda {

// A patch set's surface tree as the kernel reads it: the tree's nodes and EV bottoms as they
// are, 16 control points per regular patch (PatchSet::regular.bspline) and per FAS leaf (its
// gathered net, core/surface/surface_evaluation.h's gatherFasLeafNet), and each FAS leaf's ring centre.
struct SurfaceView {
  const SurfaceNode* nodes = nullptr;
  const EvBottom* evBottoms = nullptr;
  const Vec3* regularNets = nullptr;
  const Vec3* fasNets = nullptr;
  const Vec3* fasCenters = nullptr;
};

// One request's vertices: where each is asked for (the stitching's requests, each in its tile,
// which starts the descent at its node) and where its position and normal go.
struct VertexView {
  SurfaceView surface;
  const NodeSquare* tileNodes = nullptr;
  const VertexRequest* requests = nullptr;
  uint64_t count = 0;
  Vec3* positions = nullptr;
  Vec3* normals = nullptr;
};

// Leaf `node`'s piece (SurfaceEvaluator::leafNet's, from the flat arrays).
TESSERA_HD PieceNet leafPiece(const SurfaceView& surface, uint32_t node) {
  const SurfaceNode& leaf = surface.nodes[node];
  if (leaf.kind == NodeKind::kEvBottom) {
    const EvBottom& bottom = surface.evBottoms[leaf.payload];
    // EvBottom::g is a std::array: its points start where it does.
    return {reinterpret_cast<const Vec3*>(&bottom.g), true, 0, Vec3d(bottom.center)};
  }
  if (leaf.kind == NodeKind::kRegularLeaf) return {surface.regularNets + 16 * size_t(leaf.payload), false, leaf.orientation, Vec3d()};
  return {surface.fasNets + 16 * size_t(leaf.payload), false, leaf.orientation, Vec3d(surface.fasCenters[leaf.payload])};
}

TESSERA_HD void evaluateVertex(const VertexView& view, uint64_t i) {
  const VertexRequest request = view.requests[i];
  const LeafPoint at = descendToLeaf(view.surface.nodes, view.tileNodes[request.tile], request.u, request.v);
  const SurfaceSample sample = samplePiece<Vec3d>(leafPiece(view.surface, at.leaf.node), at.x, at.y);
  view.positions[i] = Vec3(sample.position);
  view.normals[i] = Vec3(sample.normal);
}

}  // namespace tessera::cuda
