// The nearest point of a triangle mesh to a query point: a bounding-volume hierarchy of
// axis-aligned boxes over the triangles (median splits along the longest axis, built in
// parallel), searched nearest-box-first, with the exact point-triangle distance of Ericson,
// Real-Time Collision Detection, §5.1.5. Queries are const and thread-safe.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/base/vec3.h"

namespace tessera::testing {

// Closest point of triangle (a, b, c) to p (Ericson §5.1.5: Voronoi regions of the corners and
// edges, else the projection onto the plane).
Vec3d closestPointOnTriangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c);

class TriangleBvh {
 public:
  // indices: three per triangle into positions. Both arrays are referenced, not copied (a tree
  // over 10^8 triangles must not double the mesh): they must outlive the tree.
  TriangleBvh(std::span<const Vec3> positions, std::span<const uint32_t> indices);

  struct Nearest {
    double distance = 0;
    uint32_t triangle = 0;  // index into the input triangles
    Vec3d point;
  };
  // Undefined for an empty mesh.
  Nearest nearest(const Vec3d& query) const;

  size_t triangleCount() const { return order_.size(); }

 private:
  static constexpr uint32_t kLeafSize = 4;
  struct Node {
    float lo[3];
    uint32_t rightOrFirst;  // internal: right child (the left child is the next node); leaf: first
                            // triangle
    float hi[3];
    uint32_t count;  // triangles in a leaf, 0 for an internal node
  };
  static void grow(Node& box, const Vec3& x);
  void build(uint32_t node, uint32_t begin, uint32_t end, const std::vector<Vec3>& centroids);
  Vec3 corner(uint32_t triangle, int k) const { return positions_[indices_[3 * triangle + k]]; }

  std::span<const Vec3> positions_;
  std::span<const uint32_t> indices_;
  std::vector<Node> nodes_;
  std::vector<uint32_t> order_;  // input triangles in leaf order
};

}  // namespace tessera::testing
