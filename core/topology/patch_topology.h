// What preprocessing derives from a control mesh's topology alone (paper §3.2 without the
// positions; docs/DECISIONS.md "Edits reuse topology"): the manifold sheets, OpenSubdiv's
// adaptive refinement, and which refined vertices make each regular patch and each extraordinary
// ring, with the part of a base face each covers. None of it reads a position, so a mesh with the
// same faces, creases, corners, holes, rules and UV topology (topologySha256) and moved vertices
// — a modelling tool's edited cage, a frame of an animated one — reuses all of it:
// reduceToPatches (patch_builder.h) then only refines its positions and gathers them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opensubdiv/far/topologyRefiner.h>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "core/topology/preprocessing_options.h"
#include "core/topology/ring_extraction.h"

namespace tessera {

namespace Far = OpenSubdiv::Far;

// Regular B-spline patches as refined vertices (levels concatenated, as refinedPositions lays
// them out).
struct RegularPatchLayout {
  std::vector<std::array<int, 16>> points;  // each patch's net, row-major
  std::vector<uint8_t> boundaryMasks;       // Far's boundary bits: where phantom points go
  std::vector<PatchDomain> domains;
  std::vector<uint8_t> levels;  // Far refinement level the patch was found at
  size_t size() const { return points.size(); }
};

// An extraordinary ring and the sectors it covers (patch_set.h, RingSet).
struct RingPiece {
  RingLayout layout;
  uint8_t level = 0;                        // Far refinement level the ring was taken at
  std::vector<PatchDomain> sectorDomains;   // sector i's face in its lattice frame
  std::vector<uint8_t> sectorOwned;
};

class PatchTopology {
 public:
  // Refines `mesh` (validated: validateControlMesh) with Far and lays out its pieces. Throws
  // TesseraError for unsupported input (features that cannot be reduced to the canonical pieces)
  // and for a refinement over the options' limit; calls their checkpoint and refinement hooks.
  PatchTopology(const ControlMesh& mesh, const PreprocessingOptions& options);
  ~PatchTopology();
  PatchTopology(const PatchTopology&) = delete;
  PatchTopology& operator=(const PatchTopology&) = delete;

  // Whether `mesh` has the counts this topology was made for (a cheap guard; callers key
  // topologies by topologySha256, which covers the rest).
  bool fits(const ControlMesh& mesh) const;
  // The points Far refines for `mesh`: its sheets' (manifold_sheets.h), one per sheet vertex.
  std::vector<Vec3> sheetPositions(const ControlMesh& mesh) const;
  // The sheets' faces, tags and rules, their points all at the origin: what the surface tree's
  // roots follow.
  const ControlMesh& sheetFaces() const { return sheetFaces_; }
  // The input with the sharpness OpenSubdiv implies (manifold_sheets.h, seams), its points all at
  // the origin.
  const ControlMesh& seamFaces() const { return seamFaces_; }

  const Far::TopologyRefiner& refiner() const { return *refiner_; }
  const RegularPatchLayout& regular() const { return regular_; }
  const std::vector<RingPiece>& rings() const { return rings_; }
  const PatchSetStats& stats() const { return stats_; }
  int64_t refinedVertices() const { return refinedVertices_; }
  // Frees Far's levels and the pieces' layout, keeping the faces, seams and stats: for a topology
  // no other mesh will use, once its mesh's pieces are gathered. reduceToPatches needs them.
  void releaseRefinement();
  bool holdsRefinement() const { return refiner_ != nullptr; }
  // Resident bytes, for a cache's budget (Far's levels estimated from their counts).
  size_t bytes() const;

 private:
  friend class PatchTopologyBuilder;

  int inputVertices_ = 0, inputFaces_ = 0, inputFaceVertices_ = 0;
  int64_t refinedVertices_ = 0;
  std::vector<int> sheetVertex_;  // per sheet vertex its input vertex; empty when not cut
  ControlMesh sheetFaces_, seamFaces_;
  std::unique_ptr<Far::TopologyRefiner> refiner_;
  RegularPatchLayout regular_;
  std::vector<RingPiece> rings_;
  PatchSetStats stats_;
};

// SHA-256 (hex) of everything preprocessing reads but the positions: faces, creases, corners,
// holes, the subdivision rules and the UV indices (not the UV values, nor the origin). Meshes
// with equal hashes share a PatchTopology.
std::string topologySha256(const ControlMesh& mesh);

}  // namespace tessera
