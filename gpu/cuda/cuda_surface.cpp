// Host side of the vertices on CUDA: the surface's upload, and per request the requests' upload,
// the launch and the download. The kernel is vertex_kernel.cu.
#include "gpu/cuda/cuda_surface.h"

#include <optional>

#include "gpu/cuda/cuda_runtime_support.h"
#include "gpu/cuda/surface_upload.h"
#include "gpu/cuda/vertex_launch.h"

namespace tessera::cuda {
namespace {

constexpr const char* kComponent = "CUDA vertices";

void check(cudaError_t status, const char* what) { detail::checkCuda(status, kComponent, what); }

template <class T>
detail::DeviceArray<T> upload(const std::vector<T>& host, const char* what) {
  return detail::uploadToDevice(host.data(), host.size(), kComponent, what);
}

}  // namespace

struct CudaSurface::Impl {
  SurfaceView view;  // device pointers
  size_t bytes = 0;
  detail::DeviceArray<SurfaceNode> nodes;
  detail::DeviceArray<EvBottom> evBottoms;
  detail::DeviceArray<Vec3> regularNets, fasNets, fasCenters;
};

CudaSurface::CudaSurface(const PatchSet& patches) : impl_(std::make_unique<Impl>()) {
  detail::requireCudaDevice();
  const SurfaceUpload host = makeSurfaceUpload(patches);
  Impl& d = *impl_;
  d.nodes = upload(host.nodes, "nodes upload");
  d.evBottoms = upload(host.evBottoms, "EV bottoms upload");
  d.regularNets = upload(host.regularNets, "regular nets upload");
  d.fasNets = upload(host.fasNets, "FAS nets upload");
  d.fasCenters = upload(host.fasCenters, "FAS centres upload");
  d.view = {d.nodes.get(), d.evBottoms.get(), d.regularNets.get(), d.fasNets.get(), d.fasCenters.get()};
  d.bytes = host.bytes();
}

CudaSurface::~CudaSurface() = default;

size_t CudaSurface::deviceBytes() const { return impl_->bytes; }

const SurfaceView& CudaSurface::deviceView() const { return impl_->view; }

CudaVertexEvaluation::CudaVertexEvaluation(const CudaSurface& surface) : surface_(surface) {}

CudaVertexEvaluation::~CudaVertexEvaluation() = default;

bool CudaVertexEvaluation::evaluate(const AdaptivePlan& plan, const Stitching& stitching,
                                    std::vector<Vec3>& positions, std::vector<Vec3>& normals) {
  std::vector<NodeSquare> tileNodes(plan.tiles.size());
  for (size_t t = 0; t < plan.tiles.size(); ++t) tileNodes[t] = plan.tiles[t].node;
  const size_t count = stitching.vertices.size();
  detail::TimedStream stream(kComponent);  // declared first: destroyed (synchronized) last
  const detail::StreamArray<NodeSquare> nodes(tileNodes.data(), tileNodes.size(), stream.get(), kComponent,
                                              "tile nodes upload");
  const detail::StreamArray<VertexRequest> requests(stitching.vertices.data(), count, stream.get(), kComponent,
                                                    "vertex requests upload");
  const detail::StreamArray<Vec3> outPositions(count, stream.get(), kComponent, "positions");
  const detail::StreamArray<Vec3> outNormals(count, stream.get(), kComponent, "normals");
  const VertexView view{surface_.deviceView(), nodes.get(), requests.get(), count, outPositions.get(), outNormals.get()};
  stream.timeWithoutWaiting([&] { detail::launchVertices(view, stream.get()); });
  check(cudaMemcpyAsync(positions.data(), outPositions.get(), count * sizeof(Vec3), cudaMemcpyDeviceToHost, stream.get()),
        "positions download");
  check(cudaMemcpyAsync(normals.data(), outNormals.get(), count * sizeof(Vec3), cudaMemcpyDeviceToHost, stream.get()),
        "normals download");
  stream.synchronize("vertexKernel");
  kernelMs_ = stream.elapsedMs();
  return true;
}

}  // namespace tessera::cuda
