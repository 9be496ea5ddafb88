#include "reference/ring_meshes.h"

#include <cmath>
#include <random>

namespace tessera::testing {

std::vector<int> ringFaceVertices(const cer::RingShape& shape) {
  using namespace cer;
  std::vector<int> faces;
  for (int i = 0; i < shape.sectors; ++i) {
    int next = shape.open ? i + 1 : (i + 1) % shape.sectors;
    int e = ringIndex(i, kE), a = ringIndex(i, kA), d = ringIndex(i, kD);
    int r21 = ringIndex(i, kD21), r22 = ringIndex(i, kD22), r12 = ringIndex(i, kD12);
    int eNext = ringIndex(next, kE), aNext = ringIndex(next, kA);
    for (int v : {0, e, d, eNext, e, a, r21, d, d, r21, r22, r12, eNext, d, r12, aNext}) {
      faces.push_back(v);
    }
  }
  return faces;
}

ControlMesh makeRingMesh(const cer::RingShape& shape, uint32_t seed,
                         const std::vector<uint8_t>& sharpSpokes, bool cornerEv) {
  using namespace cer;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> jitter(-0.15f, 0.15f);
  const double sweep = shape.open ? M_PI : 2.0 * M_PI;
  auto direction = [&](int spoke) {
    double angle = sweep * spoke / (shape.open ? shape.sectors : shape.sectors);
    return Vec3(float(std::cos(angle)), float(std::sin(angle)), 0.0f);
  };
  ControlMesh mesh;
  mesh.positions.resize(shape.ringPointCount());
  auto place = [&](int index, int sector, int x, int y) {
    Vec3 p = direction(sector) * float(x) + direction(sector + 1) * float(y);
    mesh.positions[index] = p + Vec3(jitter(random), jitter(random), 0.5f * jitter(random) + 0.1f * (x + y));
  };
  mesh.positions[0] = Vec3(jitter(random), jitter(random), jitter(random));
  for (int i = 0; i < shape.sectors; ++i) {
    for (int y = 0; y <= 2; ++y) {
      for (int x = 1; x <= 2; ++x) place(refinedIndexCanonical(shape, i, x, y), i, x, y);
    }
  }
  if (shape.open) {
    for (int x = 1; x <= 2; ++x) place(refinedIndexCanonical(shape, shape.sectors, x, 0), shape.sectors, x, 0);
  }
  mesh.faceVertices = ringFaceVertices(shape);
  mesh.faceSizes.assign(mesh.faceVertices.size() / 4, 4);
  for (int j = 0; j < int(sharpSpokes.size()); ++j) {
    if (!sharpSpokes[j]) continue;
    mesh.creases.push_back({0, ringIndex(j, kE), kInfiniteSharpness});
    mesh.creases.push_back({ringIndex(j, kE), ringIndex(j, kA), kInfiniteSharpness});
  }
  if (cornerEv) mesh.corners.push_back({0, kInfiniteSharpness});
  return mesh;
}

}  // namespace tessera::testing
