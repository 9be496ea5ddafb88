// A smooth edit of a control mesh's positions, the kind an animation frame or a sculpting stroke
// makes: every vertex moved by a low-frequency vector field, one sine per axis with a wavelength
// of the bounding-box diagonal, at most 1 % of the diagonal long. The topology, creases and
// holes stay. Each frame has its own phases, so that no two consecutive frames share positions
// and nothing a benchmark keeps from one frame can match the next by accident; the same frame
// always gives the same positions.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/vec3.h"
#include "core/mesh/control_mesh.h"

namespace tessera::bench {

class SmoothEdit {
 public:
  static constexpr double kRelativeAmplitude = 0.01;  // of the control mesh's box diagonal

  explicit SmoothEdit(const ControlMesh& rest);

  // The rest positions moved for `frame`, into `moved` (resized to the vertex count).
  void apply(int64_t frame, std::vector<Vec3>& moved) const;

  double diagonal() const { return diagonal_; }

 private:
  std::vector<Vec3> rest_;
  double diagonal_ = 0;
};

}  // namespace tessera::bench
