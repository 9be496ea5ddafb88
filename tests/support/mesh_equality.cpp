#include "tests/support/mesh_equality.h"

#include <cstring>
#include <vector>

namespace tessera::testing {

namespace {

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

std::string meshDifference(const TriangleMesh& a, const TriangleMesh& b) {
  if (!sameBits(a.positions, b.positions)) return "positions";
  if (!sameBits(a.normals, b.normals)) return "normals";
  if (!sameBits(a.indices, b.indices)) return "indices";
  if (std::memcmp(&a.origin, &b.origin, sizeof(Vec3d)) != 0) return "origin";
  if (!sameBits(a.uvs, b.uvs)) return "uvs";
  if (!sameBits(a.vertexFace, b.vertexFace)) return "vertexFace";
  if (!sameBits(a.vertexSubFace, b.vertexSubFace)) return "vertexSubFace";
  if (!sameBits(a.vertexUv, b.vertexUv)) return "vertexUv";
  if (!sameBits(a.vertexPoint, b.vertexPoint)) return "vertexPoint";
  if (!sameBits(a.trianglePiece, b.trianglePiece)) return "trianglePiece";
  if (!sameBits(a.triangleST, b.triangleST)) return "triangleST";
  if (!sameBits(a.triangleFace, b.triangleFace)) return "triangleFace";
  if (!sameBits(a.triangleSubFace, b.triangleSubFace)) return "triangleSubFace";
  return "";
}

}  // namespace tessera::testing
