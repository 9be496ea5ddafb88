#include "gpu/cuda/surface_upload.h"

#include "core/base/error.h"
#include "core/surface/adaptive_surface.h"
#include "core/surface/surface_evaluation.h"

namespace tessera::cuda {

size_t SurfaceUpload::bytes() const {
  auto bytesOf = [](const auto& v) { return v.size() * sizeof(v[0]); };
  return bytesOf(nodes) + bytesOf(evBottoms) + bytesOf(regularNets) + bytesOf(fasNets) + bytesOf(fasCenters);
}

SurfaceView SurfaceUpload::view() const {
  return {nodes.data(), evBottoms.data(), regularNets.data(), fasNets.data(), fasCenters.data()};
}

SurfaceUpload makeSurfaceUpload(const PatchSet& patches) {
  if (!patches.adaptive) throwUnsupported("CUDA vertices: the patch set has no surface tree");
  const SurfaceTree& tree = patches.adaptive->tree;
  SurfaceUpload upload;
  upload.nodes = tree.nodes;
  upload.evBottoms = tree.evBottoms;
  upload.regularNets.reserve(16 * patches.regular.size());
  for (const ControlNet& net : patches.regular.bspline) upload.regularNets.insert(upload.regularNets.end(), net.begin(), net.end());
  // FAS nets gathered once here (the CPU gathers them per call, keeping the last one).
  upload.fasNets.resize(16 * tree.fasLeaves.size());
  upload.fasCenters.reserve(tree.fasLeaves.size());
  for (size_t k = 0; k < tree.fasLeaves.size(); ++k) {
    gatherFasLeafNet(tree, patches, uint32_t(k), upload.fasNets.data() + 16 * k);
    upload.fasCenters.push_back(patches.rings.centers[tree.fasLeaves[k].ring]);
  }
  return upload;
}

}  // namespace tessera::cuda
