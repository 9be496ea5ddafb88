#include "core/surface/adaptive_surface.h"

namespace tessera {

size_t AdaptiveSurface::bytes() const {
  return tree.bytes() + seams.bytes() + lines.bytes();
}

std::shared_ptr<const AdaptiveSurface> buildAdaptiveSurface(const PatchSet& patches, const ControlMesh& sheetFaces,
                                                            const SeamTopology& seams, int vertexCount,
                                                            const std::function<void()>& checkpoint,
                                                            double chainFloor) {
  auto surface = std::make_shared<AdaptiveSurface>();
  surface->tree = buildSurfaceTree(patches, sheetFaces, checkpoint, chainFloor);
  if (checkpoint) checkpoint();
  surface->seams = seams;
  surface->rootSeams = RootSeams(surface->tree, surface->seams);
  surface->lines = SeamLines(surface->tree, surface->seams, vertexCount);
  return surface;
}

}  // namespace tessera
