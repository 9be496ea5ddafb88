// Texture coordinates on the limit surface: the mesh's face-varying UVs subdivided by its rules
// (Sdc's FVarLinearInterpolation among them) and evaluated at a base face's parameter, as
// OpenSubdiv defines them. Built once per mesh with UVs and kept with its patch set.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "core/mesh/control_mesh.h"

namespace tessera {

// Where one UV is wanted: a base face, its quad sub-face for an n-gon (−1 for a quad), and the
// (u, v) there (Bfr's parameterization, sub-face coordinates normalized).
struct UvQuery {
  int face = 0, subFace = -1;
  double u = 0, v = 0;
};

class LimitUvs {
 public:
  explicit LimitUvs(const ControlMesh& mesh);
  ~LimitUvs();
  LimitUvs(const LimitUvs&) = delete;
  LimitUvs& operator=(const LimitUvs&) = delete;

  // Resident bytes, for a cache's budget: each face's surface, its control indices and patch points.
  size_t bytes() const;

  // The UV at each query, on all cores.
  // `checkpoint` (may be empty, may throw: a cancelled call) is called before each batch of
  // queries a core takes (about a thousand: millions of queries are seconds of work).
  std::vector<std::array<float, 2>> evaluate(const std::vector<UvQuery>& queries,
                                             const std::function<void()>& checkpoint = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tessera
