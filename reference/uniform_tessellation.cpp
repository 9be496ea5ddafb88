#include "reference/uniform_tessellation.h"

#include <map>
#include <stdexcept>
#include <string>

#include <opensubdiv/bfr/tessellation.h>
#include <tbb/parallel_for.h>

namespace tessera::testing {

namespace Bfr = OpenSubdiv::Bfr;

namespace {

// Bfr's tessellation of one face size: coordinates (the n·R boundary points first, corner i at
// i·R followed by edge i's points towards corner i + 1, then the interior) and triangles.
struct FacePattern {
  int size = 4, boundary = 0, interior = 0;
  std::vector<double> coords;  // Bfr face coordinates, two per point
  std::vector<int> facets;     // three per triangle
  std::vector<int> subFace;    // per point: normalized sub-face (n-gons) or -1
  std::vector<double> subUv;   // per point: (u, v) in its domain
};

FacePattern patternFor(int size, int rate) {
  const Bfr::Parameterization param(OpenSubdiv::Sdc::SCHEME_CATMARK, size);
  const Bfr::Tessellation tessellation(param, rate);  // triangles by default
  FacePattern p;
  p.size = size;
  p.boundary = tessellation.GetNumBoundaryCoords();
  p.interior = tessellation.GetNumInteriorCoords();
  if (p.boundary != size * rate) {
    throw std::logic_error("Bfr puts " + std::to_string(p.boundary) +
                           " points on the border of a " + std::to_string(size) + "-gon at rate " +
                           std::to_string(rate));
  }
  p.coords.resize(2 * size_t(tessellation.GetNumCoords()));
  tessellation.GetCoords(p.coords.data());
  p.facets.resize(3 * size_t(tessellation.GetNumFacets()));
  tessellation.GetFacets(p.facets.data());
  p.subFace.assign(tessellation.GetNumCoords(), -1);
  p.subUv = p.coords;
  if (param.HasSubFaces()) {
    for (int i = 0; i < tessellation.GetNumCoords(); ++i) {
      p.subFace[i] = param.ConvertCoordToNormalizedSubFace(&p.coords[2 * i], &p.subUv[2 * i]);
    }
  }
  return p;
}

// Global vertex numbers: used base vertices, then R - 1 per used base edge, then every face's
// interior points; each shared point is evaluated by its owner, the lowest face that has it.
struct Numbering {
  std::vector<uint32_t> vertexId, edgeFirst, interiorFirst;
  std::vector<int> vertexOwner, edgeOwner;
  std::vector<size_t> triangleFirst;
  uint32_t vertices = 0;
};

Numbering number(const LimitSurface& surface, const std::map<int, FacePattern>& patterns,
                 int rate) {
  const Far::TopologyLevel& level = surface.baseLevel();
  Numbering n;
  n.vertexOwner.assign(level.GetNumVertices(), -1);
  n.edgeOwner.assign(level.GetNumEdges(), -1);
  for (int f = level.GetNumFaces() - 1; f >= 0; --f) {  // downwards: the lowest face wins
    if (surface.isHole(f)) continue;
    for (int v : level.GetFaceVertices(f)) n.vertexOwner[v] = f;
    for (int e : level.GetFaceEdges(f)) n.edgeOwner[e] = f;
  }
  uint64_t next = 0;
  n.vertexId.assign(level.GetNumVertices(), 0);
  for (int v = 0; v < level.GetNumVertices(); ++v) {
    n.vertexId[v] = uint32_t(next);
    next += n.vertexOwner[v] >= 0 ? 1 : 0;
  }
  n.edgeFirst.assign(level.GetNumEdges(), 0);
  for (int e = 0; e < level.GetNumEdges(); ++e) {
    n.edgeFirst[e] = uint32_t(next);
    next += n.edgeOwner[e] >= 0 ? rate - 1 : 0;
  }
  n.interiorFirst.assign(level.GetNumFaces(), 0);
  n.triangleFirst.assign(level.GetNumFaces() + 1, 0);
  for (int f = 0; f < level.GetNumFaces(); ++f) {
    n.interiorFirst[f] = uint32_t(next);
    const FacePattern* p =
        surface.isHole(f) ? nullptr : &patterns.at(level.GetFaceVertices(f).size());
    next += p ? p->interior : 0;
    n.triangleFirst[f + 1] = n.triangleFirst[f] + (p ? p->facets.size() / 3 : 0);
  }
  if (next > UINT32_MAX) throw std::length_error("uniform tessellation: more than 2^32 vertices");
  n.vertices = uint32_t(next);
  return n;
}

// Global number of point i of face f's pattern, and whether f evaluates it.
uint32_t pointId(const Far::TopologyLevel& level, const Numbering& n, const FacePattern& p,
                 int rate, int f, int i, bool& owned) {
  if (i >= p.boundary) {
    owned = true;
    return n.interiorFirst[f] + uint32_t(i - p.boundary);
  }
  const int side = i / rate, along = i % rate;
  if (along == 0) {
    const int v = level.GetFaceVertices(f)[side];
    owned = n.vertexOwner[v] == f;
    return n.vertexId[v];
  }
  const int e = level.GetFaceEdges(f)[side];
  owned = n.edgeOwner[e] == f;
  const bool forward = level.GetEdgeVertices(e)[0] == level.GetFaceVertices(f)[side];
  return n.edgeFirst[e] + uint32_t((forward ? along : rate - along) - 1);
}

// (u, v) of a point of sub-face `from` in the chart of sub-face `to` of the same n-gon, unfolded
// as a quad's neighbouring sub-faces would be; false when the two are not neighbours.
bool unfold(int size, int from, int to, double s, double t, double out[2]) {
  if (s == 1 && t == 1) from = to;  // the face centre is (1, 1) in every sub-face
  if (from == to) {
    out[0] = s, out[1] = t;
  } else if (from == (to + 1) % size) {
    out[0] = 2 - t, out[1] = s;
  } else if (to == (from + 1) % size) {
    out[0] = t, out[1] = 2 - s;
  } else {
    return false;
  }
  return true;
}

// The sub-face of a triangle of an n-gon: the corner sub-face into which most corners unfold.
void triangleDomain(const FacePattern& p, const int corner[3], int& subFace, double uv[6]) {
  int bestCount = -1;
  for (int candidate = 0; candidate < 3; ++candidate) {
    const int k = p.subFace[corner[candidate]];
    double trial[6];
    int count = 0;
    for (int c = 0; c < 3; ++c) {
      const int i = corner[c];
      if (unfold(p.size, p.subFace[i], k, p.subUv[2 * i], p.subUv[2 * i + 1], trial + 2 * c)) {
        ++count;
      } else {
        trial[2 * c] = trial[2 * c + 1] = 1.0;  // not a neighbour: the face centre
      }
    }
    if (count > bestCount) bestCount = count, subFace = k, std::copy(trial, trial + 6, uv);
  }
}

void tessellateFace(const LimitSurface& surface, const FacePattern& p, const Numbering& n, int rate,
                    int f, UniformTessellation& out) {
  const Far::TopologyLevel& level = surface.baseLevel();
  std::vector<uint32_t> ids(p.subFace.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    bool owned = false;
    ids[i] = pointId(level, n, p, rate, f, int(i), owned);
    if (!owned) continue;
    Vec3d x;
    surface.evaluate(surface.domainOf(f, p.subFace[i]), p.subUv[2 * i], p.subUv[2 * i + 1], x);
    out.positions[ids[i]] = Vec3(x);
  }
  for (size_t t = 0; t < p.facets.size() / 3; ++t) {
    const size_t global = n.triangleFirst[f] + t;
    const int* corner = &p.facets[3 * t];
    for (int c = 0; c < 3; ++c) out.indices[3 * global + c] = ids[corner[c]];
    out.triangleFace[global] = f;
    double* uv = &out.cornerUv[6 * global];
    if (p.size == 4) {
      out.triangleSubFace[global] = -1;
      for (int k = 0; k < 6; ++k) uv[k] = p.coords[2 * corner[k / 2] + k % 2];
    } else {
      triangleDomain(p, corner, out.triangleSubFace[global], uv);
    }
  }
}

}  // namespace

TriangleMeshView UniformTessellation::view() const {
  TriangleMeshView v;
  v.positions = positions;
  v.indices = indices;
  v.triangleFace = triangleFace;
  v.triangleSubFace = triangleSubFace;
  v.cornerUv = cornerUv;
  return v;
}

UniformTessellation tessellateUniform(const LimitSurface& surface, int rate) {
  if (rate < 1) throw std::invalid_argument("uniform tessellation: the rate must be at least 1");
  const Far::TopologyLevel& level = surface.baseLevel();
  std::map<int, FacePattern> patterns;
  for (int f = 0; f < level.GetNumFaces(); ++f) {
    const int size = level.GetFaceVertices(f).size();
    if (!surface.isHole(f) && !patterns.count(size)) patterns.emplace(size, patternFor(size, rate));
  }
  const Numbering n = number(surface, patterns, rate);
  UniformTessellation out;
  const size_t triangles = n.triangleFirst.back();
  out.positions.resize(n.vertices);
  out.indices.resize(3 * triangles);
  out.triangleFace.resize(triangles);
  out.triangleSubFace.resize(triangles);
  out.cornerUv.resize(6 * triangles);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, level.GetNumFaces(), 8), [&](const tbb::blocked_range<int>& r) {
        for (int f = r.begin(); f != r.end(); ++f) {
          if (surface.isHole(f)) continue;
          tessellateFace(surface, patterns.at(level.GetFaceVertices(f).size()), n, rate, f, out);
        }
      });
  return out;
}

size_t uniformTriangleCount(const LimitSurface& surface, int rate) {
  if (rate < 1) throw std::invalid_argument("uniform tessellation: the rate must be at least 1");
  const Far::TopologyLevel& level = surface.baseLevel();
  std::map<int, size_t> facetsPerSize;
  size_t triangles = 0;
  for (int f = 0; f < level.GetNumFaces(); ++f) {
    if (surface.isHole(f)) continue;
    const int size = level.GetFaceVertices(f).size();
    auto found = facetsPerSize.find(size);
    if (found == facetsPerSize.end()) {
      const Bfr::Parameterization param(OpenSubdiv::Sdc::SCHEME_CATMARK, size);
      found =
          facetsPerSize.emplace(size, size_t(Bfr::Tessellation(param, rate).GetNumFacets())).first;
    }
    triangles += found->second;
  }
  return triangles;
}

}  // namespace tessera::testing
