// An independent reference for frames of a limit surface: OpenSubdiv Bfr (exact limit
// evaluation, approximation levels raised to 10 as in reference/bfr_reference.h) on a
// uniform G×G grid of every base face, the same G on every face so that neighbours meet without
// T-junctions. Each grid is also sampled at its edge and diagonal midpoints (a 2G grid), which
// measures how far the reference's own triangles are from the surface.
#pragma once

#include <functional>
#include <vector>

#include "core/base/vec3.h"
#include "core/mesh/control_mesh.h"
#include "gpu/vulkan/render_types.h"

namespace tessera::testing {

struct FaceGrid {
  int face = 0;
  std::vector<Vec3d> fine;  // (2G+1)² limit points, row-major in (u, v); even ones are vertices
  std::vector<Vec3d> du, dv, duv;  // (G+1)² derivatives at the vertices
};

struct ReferenceSurface {
  int cells = 0;  // G
  std::vector<FaceGrid> grids;
  Vec3d vertex(const FaceGrid& g, int i, int j) const {
    return g.fine[size_t(2 * j) * (2 * cells + 1) + 2 * i];
  }
};

// The non-hole base faces of `mesh` that `keep` accepts (all when empty), on a G×G grid. Quads
// only (the models these tests use); other faces are reported as a test failure.
ReferenceSurface buildReferenceSurface(const ControlMesh& mesh, int cells,
                                       const std::function<bool(int face)>& keep = {});

// Pinhole projection with exactly the renderer's conventions (gpu/vulkan/camera_math.cpp):
// right-handed view looking down -z, vertical fov, aspect = width/height, framebuffer row 0 at
// the top, pixel (i, j) centred at (i + 0.5, j + 0.5), window depth 0 at near and 1 at far.
// Written independently, in double precision.
class Pinhole {
 public:
  Pinhole(const gpu::Camera& camera, double nearPlane, double farPlane);
  struct Window {
    double x, y;   // pixels
    double w;      // distance along the view direction
    double depth;  // window depth, [0, 1] between the planes
  };
  Window project(const Vec3d& p) const;
  double nearPlane() const { return near_; }
  double width() const { return width_; }
  double height() const { return height_; }

 private:
  Vec3d eye_, right_, up_, forward_;
  double focal_, aspect_, near_, far_;
  double width_, height_;
};

// Faces with a grid cell whose corners, in front of the eye, span a box within `margin` pixels
// of the viewport (the margin must cover the grid's own error).
std::vector<uint8_t> facesInView(const ReferenceSurface& reference, const Pinhole& pinhole,
                                 int faceCount, double margin);

// The largest screen-space offset between the reference's triangles and the surface, from the
// midpoint samples: each sample's offset from its chord along the cell normal, projected. For a
// locally quadratic surface the offset over a triangle peaks at most 4/3 times its largest
// edge-midpoint value (it is Σ λiλj δij; Σ λiλj is 1/3 at the centroid, 1/4 at a midpoint), so
// that factor is applied. Offsets within the surface (non-uniform parameterisation next to
// extraordinary vertices) move no silhouette and are not counted.
double referenceErrorPixels(const ReferenceSurface& reference, const Pinhole& pinhole);

// Z-buffered rasterisation of the reference's triangles (two per cell, split along the (0,0)-
// (1,1) diagonal) at pixel centres, edges inclusive. Triangles with a corner not beyond the near
// plane are counted in `clipped` and skipped (test cameras keep the surface in front).
struct CpuRaster {
  int width = 0, height = 0;
  std::vector<double> depth;     // window depth; > 1 where nothing was drawn
  std::vector<uint8_t> covered;  // 1 where a triangle covers the pixel centre
  size_t clipped = 0;
};
CpuRaster rasterizeReference(const ReferenceSurface& reference, const Pinhole& pinhole, int width,
                             int height);

// The reference as render patches for the renderer's own shading. Per face `cellsPerFace`²
// bicubic Hermite cells (Bfr's position, first derivatives and twist at the four corners; exact
// wherever the limit surface is one bicubic over the cell), each tessellated at level
// L = G / cellsPerFace so that its vertices fall on the reference grid: one draw per cell
// instead of one per grid square keeps the frame affordable on lavapipe. Every vertex the
// renderer will make of a cell is checked against Bfr (screen distance, normal angle); a cell
// over `maxPixels` or `maxDegrees` (next to extraordinary vertices, where Bfr's derivatives are
// singular) is replaced by its L² grid squares at level 1, whose vertices are Bfr's points with
// Bfr's normals (the squares' corner derivatives are Bfr's, twist zero).
struct ShadingReference {
  std::vector<gpu::RenderPatch> patches;
  double positionPixels = 0;  // largest vertex offset from Bfr, over the accepted Hermite cells
  double normalDegrees = 0;   // largest vertex normal angle from Bfr's
  size_t hermiteCells = 0, exactSquares = 0;
};
ShadingReference shadingReference(const ReferenceSurface& reference, int cellsPerFace,
                                  const Pinhole& pinhole, double maxPixels, double maxDegrees);

}  // namespace tessera::testing
