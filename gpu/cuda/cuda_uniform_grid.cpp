// Host side of the uniform grid on CUDA: the upload of nets, pieces and offsets, launches and
// timing. The kernel is uniform_grid_kernel.cu.
#include "gpu/cuda/cuda_uniform_grid.h"

#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "gpu/cuda/cuda_runtime_support.h"
#include "gpu/cuda/grid_launch.h"

namespace tessera::cuda {
namespace {

constexpr const char* kComponent = "CUDA uniform grid";

void check(cudaError_t status, const char* what) {
  detail::checkCuda(status, kComponent, what);
}

}  // namespace

GridUpload makeGridUpload(const PatchSet& patches, const UniformGrid& grid) {
  GridUpload upload;
  std::map<std::pair<int, NetBasis>, uint32_t> tables;  // (level, basis) -> first weights
  upload.nets.reserve(grid.pieces.size() * 16);
  upload.pieces.reserve(grid.pieces.size());
  for (size_t q = 0; q < grid.pieces.size(); ++q) {
    const ControlNet& net =
        q < grid.regularPieces ? patches.regular.bspline[q] : grid.ringNets[q - grid.regularPieces];
    upload.nets.insert(upload.nets.end(), net.begin(), net.end());
    const GridPiece piece = grid.pieces[q];
    auto [table, added] = tables.try_emplace({piece.level, piece.basis}, upload.weights.size());
    if (added) {
      for (int i = 0; i <= piece.level; ++i) {
        gridWeights(piece.basis, i, piece.level, upload.weights.emplace_back().w);
      }
    }
    upload.pieces.push_back({piece.level, table->second});
  }
  upload.offsets.assign(grid.offsets.begin(), grid.offsets.end());
  if (upload.offsets.empty()) upload.offsets.push_back(0);
  return upload;
}

struct CudaUniformGrid::Impl {
  GridView view;  // device pointers
  detail::DeviceArray<Vec3> nets, out;
  detail::DeviceArray<GridPieceRecord> pieces;
  detail::DeviceArray<ParameterWeights> weights;
  detail::DeviceArray<uint64_t> offsets;
  detail::DeviceArray<uint32_t> blockFirstPiece;
  std::optional<detail::TimedStream> stream;  // created once a device is known; destroyed first
};

CudaUniformGrid::CudaUniformGrid(const PatchSet& patches, const UniformGrid& grid)
    : impl_(std::make_unique<Impl>()) {
  if (grid.pieces.size() > UINT32_MAX) {
    throwLimit("CUDA uniform grid: " + std::to_string(grid.pieces.size()) +
               " pieces; at most 2^32 - 1 in one grid");
  }
  detail::requireCudaDevice();
  const GridUpload upload = makeGridUpload(patches, grid);
  Impl& s = *impl_;
  s.stream.emplace(kComponent);
  s.nets = detail::uploadToDevice(upload.nets.data(), upload.nets.size(), kComponent, "nets");
  s.pieces =
      detail::uploadToDevice(upload.pieces.data(), upload.pieces.size(), kComponent, "pieces");
  s.weights =
      detail::uploadToDevice(upload.weights.data(), upload.weights.size(), kComponent, "weights");
  s.offsets =
      detail::uploadToDevice(upload.offsets.data(), upload.offsets.size(), kComponent, "offsets");
  s.view.pieceCount = upload.pieces.size();
  s.view.sampleCount = upload.offsets.back();
  s.blockFirstPiece =
      detail::allocateDevice<uint32_t>(s.view.blocks(), kComponent, "cudaMalloc(block pieces)");
  s.view.blockFirstPiece = s.blockFirstPiece.get();
  s.out = detail::allocateDevice<Vec3>(s.view.sampleCount, kComponent, "cudaMalloc(samples)");
  s.view.nets = s.nets.get();
  s.view.pieces = s.pieces.get();
  s.view.weights = s.weights.get();
  s.view.offsets = s.offsets.get();
  s.view.out = s.out.get();
}

CudaUniformGrid::~CudaUniformGrid() = default;

void CudaUniformGrid::launch() {
  detail::launchUniformGrid(impl_->view, impl_->stream->get());
}

float CudaUniformGrid::timeKernelMs(int repetitions) {
  if (repetitions < 1) throwInvalid("CUDA uniform grid: timing needs at least 1 repetition");
  return impl_->stream->meanMs(repetitions, [this] { launch(); });
}

std::vector<Vec3> CudaUniformGrid::download() {
  Impl& s = *impl_;
  s.stream->synchronize("uniformGridKernel");
  std::vector<Vec3> samples(s.view.sampleCount);
  if (!samples.empty()) {
    check(cudaMemcpy(samples.data(), s.out.get(), samples.size() * sizeof(Vec3),
                     cudaMemcpyDeviceToHost),
          "cudaMemcpy(samples)");
  }
  return samples;
}

size_t CudaUniformGrid::samples() const {
  return impl_->view.sampleCount;
}
const Vec3* CudaUniformGrid::deviceSamples() const {
  return impl_->out.get();
}

}  // namespace tessera::cuda
