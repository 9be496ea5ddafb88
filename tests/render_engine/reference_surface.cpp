#include "tests/render_engine/reference_surface.h"

#include <gtest/gtest.h>
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "core/topology/far_topology.h"

namespace tessera::testing {
namespace {

namespace Bfr = OpenSubdiv::Bfr;

// Bfr on one base face at a time, with second derivatives (for the Hermite cells' twists).
class LimitEvaluator {
 public:
  explicit LimitEvaluator(const ControlMesh& mesh) : refiner_(createTopologyRefiner(mesh)) {
    for (const Vec3& p : mesh.positions) meshPoints_.insert(meshPoints_.end(), {p.x, p.y, p.z});
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(10).SetApproxLevelSharp(10);
    factory_ = std::make_unique<Bfr::RefinerSurfaceFactory<>>(*refiner_, options);
  }

  // False for a hole or a face without a limit surface.
  bool select(int face) {
    if (!factory_->InitVertexSurface(face, &surface_)) return false;
    patchPoints_.resize(size_t(surface_.GetNumPatchPoints()) * 3);
    surface_.PreparePatchPoints(meshPoints_.data(), 3, patchPoints_.data(), 3);
    return true;
  }
  int faceSize() const { return surface_.GetFaceSize(); }

  Vec3d position(double u, double v) const {
    double uv[2] = {u, v}, p[3];
    surface_.Evaluate(uv, patchPoints_.data(), 3, p);
    return {p[0], p[1], p[2]};
  }
  void derivatives(double u, double v, Vec3d& du, Vec3d& dv, Vec3d& duv) const {
    double uv[2] = {u, v}, p[3], pu[3], pv[3], puu[3], puv[3], pvv[3];
    surface_.Evaluate(uv, patchPoints_.data(), 3, p, pu, pv, puu, puv, pvv);
    du = {pu[0], pu[1], pu[2]};
    dv = {pv[0], pv[1], pv[2]};
    duv = {puv[0], puv[1], puv[2]};
  }

 private:
  std::vector<double> meshPoints_;
  std::unique_ptr<Far::TopologyRefiner> refiner_;
  std::unique_ptr<Bfr::RefinerSurfaceFactory<>> factory_;
  Bfr::Surface<double> surface_;
  std::vector<double> patchPoints_;
};

bool isHole(const ControlMesh& mesh, int face) {
  return std::find(mesh.holes.begin(), mesh.holes.end(), face) != mesh.holes.end();
}

void sampleGrid(const LimitEvaluator& limit, int cells, FaceGrid& grid) {
  const int fine = 2 * cells;
  grid.fine.resize(size_t(fine + 1) * (fine + 1));
  grid.du.resize(size_t(cells + 1) * (cells + 1));
  grid.dv.resize(grid.du.size());
  grid.duv.resize(grid.du.size());
  for (int j = 0; j <= fine; ++j) {
    for (int i = 0; i <= fine; ++i) {
      double u = double(i) / fine, v = double(j) / fine;
      grid.fine[size_t(j) * (fine + 1) + i] = limit.position(u, v);
      if (i % 2 == 0 && j % 2 == 0) {
        size_t k = size_t(j / 2) * (cells + 1) + i / 2;
        limit.derivatives(u, v, grid.du[k], grid.dv[k], grid.duv[k]);
      }
    }
  }
}

}  // namespace

ReferenceSurface buildReferenceSurface(const ControlMesh& mesh, int cells,
                                       const std::function<bool(int face)>& keep) {
  LimitEvaluator limit(mesh);
  ReferenceSurface out;
  out.cells = cells;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    if (isHole(mesh, f) || (keep && !keep(f)) || !limit.select(f)) continue;
    if (limit.faceSize() != 4) {
      ADD_FAILURE() << "the reference grid takes quads only; face " << f << " has "
                    << limit.faceSize() << " sides";
      continue;
    }
    FaceGrid grid;
    grid.face = f;
    sampleGrid(limit, cells, grid);
    out.grids.push_back(std::move(grid));
  }
  return out;
}

Pinhole::Pinhole(const gpu::Camera& camera, double nearPlane, double farPlane)
    : eye_(camera.eye),
      near_(nearPlane),
      far_(farPlane),
      width_(camera.width),
      height_(camera.height) {
  Vec3d view = Vec3d(camera.target) - eye_;
  forward_ = view * (1.0 / length(view));
  Vec3d side = cross(forward_, Vec3d(camera.up));
  right_ = side * (1.0 / length(side));
  up_ = cross(right_, forward_);
  focal_ = 1.0 / std::tan(double(camera.fovYDegrees) * M_PI / 360.0);
  aspect_ = width_ / height_;
}

Pinhole::Window Pinhole::project(const Vec3d& p) const {
  Vec3d d = p - eye_;
  Window out;
  out.w = dot(d, forward_);
  double ndcX = focal_ / aspect_ * dot(d, right_) / out.w;
  double ndcY = -focal_ * dot(d, up_) / out.w;  // framebuffer y points down
  out.x = (ndcX + 1.0) * 0.5 * width_;
  out.y = (ndcY + 1.0) * 0.5 * height_;
  // Reversed-free [0,1] depth of a standard perspective: 0 at near, 1 at far.
  out.depth = far_ / (far_ - near_) * (1.0 - near_ / out.w);
  return out;
}

std::vector<uint8_t> facesInView(const ReferenceSurface& reference, const Pinhole& pinhole,
                                 int faceCount, double margin) {
  std::vector<uint8_t> visible(size_t(faceCount), 0);
  const int g = reference.cells;
  for (const FaceGrid& grid : reference.grids) {
    std::vector<Pinhole::Window> p(size_t(g + 1) * (g + 1));
    for (int j = 0; j <= g; ++j) {
      for (int i = 0; i <= g; ++i)
        p[size_t(j) * (g + 1) + i] = pinhole.project(reference.vertex(grid, i, j));
    }
    for (int j = 0; j < g && !visible[size_t(grid.face)]; ++j) {
      for (int i = 0; i < g; ++i) {
        const Pinhole::Window* c[4] = {&p[size_t(j) * (g + 1) + i], &p[size_t(j) * (g + 1) + i + 1],
                                       &p[size_t(j + 1) * (g + 1) + i],
                                       &p[size_t(j + 1) * (g + 1) + i + 1]};
        double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
        bool inFront = true;
        for (const Pinhole::Window* w : c) {
          inFront &= w->w > 0;
          x0 = std::min(x0, w->x), x1 = std::max(x1, w->x), y0 = std::min(y0, w->y),
          y1 = std::max(y1, w->y);
        }
        if (inFront && x1 > -margin && y1 > -margin && x0 < pinhole.width() + margin &&
            y0 < pinhole.height() + margin) {
          visible[size_t(grid.face)] = 1;
          break;
        }
      }
    }
  }
  return visible;
}

double referenceErrorPixels(const ReferenceSurface& reference, const Pinhole& pinhole) {
  const int n = 2 * reference.cells + 1;
  double worst = 0;
  for (const FaceGrid& g : reference.grids) {
    auto at = [&](int i, int j) { return g.fine[size_t(j) * n + i]; };
    // The surface point's offset from the chord along the cell's normal, seen on screen.
    // Offsets within the surface (a parameterisation that is not uniform, as next to
    // extraordinary vertices) move no silhouette and are left out.
    auto check = [&](const Vec3d& surface, const Vec3d& a, const Vec3d& b, const Vec3d& normal) {
      Vec3d foot = surface - normal * dot(surface - (a + b) * 0.5, normal);
      Pinhole::Window s = pinhole.project(surface), f = pinhole.project(foot);
      if (s.w <= 0 || f.w <= 0) return;
      worst = std::max(worst, std::hypot(s.x - f.x, s.y - f.y));
    };
    for (int j = 0; j + 2 < n; j += 2) {
      for (int i = 0; i + 2 < n; i += 2) {
        Vec3d c = cross(at(i + 2, j + 2) - at(i, j), at(i, j + 2) - at(i + 2, j));
        if (!(length(c) > 0)) continue;
        Vec3d normal = c * (1.0 / length(c));
        check(at(i + 1, j), at(i, j), at(i + 2, j), normal);
        check(at(i + 1, j + 2), at(i, j + 2), at(i + 2, j + 2), normal);
        check(at(i, j + 1), at(i, j), at(i, j + 2), normal);
        check(at(i + 2, j + 1), at(i + 2, j), at(i + 2, j + 2), normal);
        check(at(i + 1, j + 1), at(i, j), at(i + 2, j + 2), normal);
      }
    }
  }
  return worst * 4.0 / 3.0;
}

namespace {

void rasterizeTriangle(const Pinhole::Window (&v)[3], CpuRaster& out) {
  double area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
  if (area == 0.0) return;
  const double sign = area > 0 ? 1.0 : -1.0;
  int x0 = std::max(0, int(std::floor(std::min({v[0].x, v[1].x, v[2].x}) - 0.5)));
  int x1 = std::min(out.width - 1, int(std::ceil(std::max({v[0].x, v[1].x, v[2].x}))));
  int y0 = std::max(0, int(std::floor(std::min({v[0].y, v[1].y, v[2].y}) - 0.5)));
  int y1 = std::min(out.height - 1, int(std::ceil(std::max({v[0].y, v[1].y, v[2].y}))));
  for (int py = y0; py <= y1; ++py) {
    for (int px = x0; px <= x1; ++px) {
      double cx = px + 0.5, cy = py + 0.5;
      double b[3];
      for (int e = 0; e < 3; ++e) {
        const Pinhole::Window& a = v[(e + 1) % 3];
        const Pinhole::Window& c = v[(e + 2) % 3];
        b[e] = sign * ((c.x - a.x) * (cy - a.y) - (cx - a.x) * (c.y - a.y));
      }
      if (b[0] < 0 || b[1] < 0 || b[2] < 0) continue;
      // Window depth is affine in screen space (z/w of a projected plane).
      double total = b[0] + b[1] + b[2];
      double depth = (b[0] * v[0].depth + b[1] * v[1].depth + b[2] * v[2].depth) / total;
      size_t k = size_t(py) * out.width + px;
      out.covered[k] = 1;
      out.depth[k] = std::min(out.depth[k], depth);
    }
  }
}

}  // namespace

CpuRaster rasterizeReference(const ReferenceSurface& reference, const Pinhole& pinhole, int width,
                             int height) {
  CpuRaster out;
  out.width = width;
  out.height = height;
  out.depth.assign(size_t(width) * height, std::numeric_limits<double>::infinity());
  out.covered.assign(size_t(width) * height, 0);
  const int g = reference.cells;
  for (const FaceGrid& grid : reference.grids) {
    std::vector<Pinhole::Window> projected(size_t(g + 1) * (g + 1));
    for (int j = 0; j <= g; ++j) {
      for (int i = 0; i <= g; ++i)
        projected[size_t(j) * (g + 1) + i] = pinhole.project(reference.vertex(grid, i, j));
    }
    for (int j = 0; j < g; ++j) {
      for (int i = 0; i < g; ++i) {
        const Pinhole::Window& p00 = projected[size_t(j) * (g + 1) + i];
        const Pinhole::Window& p10 = projected[size_t(j) * (g + 1) + i + 1];
        const Pinhole::Window& p01 = projected[size_t(j + 1) * (g + 1) + i];
        const Pinhole::Window& p11 = projected[size_t(j + 1) * (g + 1) + i + 1];
        const Pinhole::Window tris[2][3] = {{p00, p10, p11}, {p00, p11, p01}};
        for (const auto& t : tris) {
          if (t[0].w <= pinhole.nearPlane() || t[1].w <= pinhole.nearPlane() ||
              t[2].w <= pinhole.nearPlane()) {
            ++out.clipped;
            continue;
          }
          rasterizeTriangle(t, out);
        }
      }
    }
  }
  return out;
}

namespace {

// Bicubic Hermite cell of one face's grid: corners at vertices (ci·L, cj·L), (ci+1)·L, ...,
// parameter size h = L / G (L = step). At corner c the neighbouring control points follow its
// derivatives (b10 = P + h/3·Pu, ...) and the inner one its twist (+ h²/9·Puv), so the patch
// has the corner's position, tangent plane and twist.
std::array<Vec3d, 16> hermiteCell(const ReferenceSurface& reference, const FaceGrid& grid, int ci,
                                  int cj, int step, bool withTwist) {
  const int g = reference.cells;
  const double h = double(step) / g;
  std::array<Vec3d, 16> b;
  for (int cy = 0; cy < 2; ++cy) {
    for (int cx = 0; cx < 2; ++cx) {
      int vi = (ci + cx) * step, vj = (cj + cy) * step;
      size_t k = size_t(vj) * (g + 1) + vi;
      double su = cx == 0 ? 1 : -1, sv = cy == 0 ? 1 : -1;
      Vec3d p = reference.vertex(grid, vi, vj);
      Vec3d du = grid.du[k] * (su * h / 3), dv = grid.dv[k] * (sv * h / 3);
      Vec3d twist = withTwist ? grid.duv[k] * (su * sv * h * h / 9) : Vec3d();
      int bi = 3 * cx, bj = 3 * cy, ni = cx == 0 ? 1 : 2, nj = cy == 0 ? 1 : 2;
      b[size_t(4 * bj + bi)] = p;
      b[size_t(4 * bj + ni)] = p + du;
      b[size_t(4 * nj + bi)] = p + dv;
      b[size_t(4 * nj + ni)] = p + du + dv + twist;
    }
  }
  return b;
}

void bernstein(double t, double w[4], double d[4]) {
  double s = 1 - t;
  w[0] = s * s * s, w[1] = 3 * t * s * s, w[2] = 3 * t * t * s, w[3] = t * t * t;
  d[0] = -3 * s * s, d[1] = 3 * s * s - 6 * t * s, d[2] = 6 * t * s - 3 * t * t, d[3] = 3 * t * t;
}

void evaluateCell(const std::array<Vec3d, 16>& b, double s, double t, Vec3d& p, Vec3d& normal) {
  double ws[4], ds[4], wt[4], dt[4];
  bernstein(s, ws, ds);
  bernstein(t, wt, dt);
  Vec3d ps, pt;
  p = ps = pt = Vec3d();
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      p += b[size_t(4 * j + i)] * (ws[i] * wt[j]);
      ps += b[size_t(4 * j + i)] * (ds[i] * wt[j]);
      pt += b[size_t(4 * j + i)] * (ws[i] * dt[j]);
    }
  }
  normal = cross(ps, pt);
}

double angleDegrees(const Vec3d& a, const Vec3d& b) {
  double la = length(a), lb = length(b);
  if (!(la > 0 && lb > 0)) return 0;
  return std::acos(std::clamp(dot(a, b) / (la * lb), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

namespace {

gpu::RenderPatch toRenderPatch(const std::array<Vec3d, 16>& b, uint32_t level, uint32_t id) {
  gpu::RenderPatch patch{};
  for (int q = 0; q < 16; ++q) {
    patch.controlPoints[q][0] = float(b[size_t(q)].x);
    patch.controlPoints[q][1] = float(b[size_t(q)].y);
    patch.controlPoints[q][2] = float(b[size_t(q)].z);
  }
  for (uint32_t& e : patch.edgeLevels) e = level;
  patch.patchId = id;
  return patch;
}

}  // namespace

ShadingReference shadingReference(const ReferenceSurface& reference, int cellsPerFace,
                                  const Pinhole& pinhole, double maxPixels, double maxDegrees) {
  const int g = reference.cells, step = g / cellsPerFace;
  ShadingReference out;
  uint32_t id = 0;
  for (const FaceGrid& grid : reference.grids) {
    for (int cj = 0; cj < cellsPerFace; ++cj) {
      for (int ci = 0; ci < cellsPerFace; ++ci) {
        std::array<Vec3d, 16> b = hermiteCell(reference, grid, ci, cj, step, true);
        double pixels = 0, degrees = 0;
        for (int y = 0; y <= step; ++y) {
          for (int x = 0; x <= step; ++x) {
            Vec3d p, normal;
            evaluateCell(b, double(x) / step, double(y) / step, p, normal);
            int vi = ci * step + x, vj = cj * step + y;
            size_t k = size_t(vj) * (g + 1) + vi;
            Pinhole::Window a = pinhole.project(p),
                            e = pinhole.project(reference.vertex(grid, vi, vj));
            pixels = std::max(pixels, std::hypot(a.x - e.x, a.y - e.y));
            degrees = std::max(degrees, angleDegrees(normal, cross(grid.du[k], grid.dv[k])));
          }
        }
        if (pixels <= maxPixels && degrees <= maxDegrees) {
          out.positionPixels = std::max(out.positionPixels, pixels);
          out.normalDegrees = std::max(out.normalDegrees, degrees);
          out.patches.push_back(toRenderPatch(b, uint32_t(step), id++));
          ++out.hermiteCells;
          continue;
        }
        for (int y = 0; y < step; ++y) {
          for (int x = 0; x < step; ++x) {
            out.patches.push_back(toRenderPatch(
                hermiteCell(reference, grid, ci * step + x, cj * step + y, 1, false), 1, id++));
            ++out.exactSquares;
          }
        }
      }
    }
  }
  return out;
}

}  // namespace tessera::testing
