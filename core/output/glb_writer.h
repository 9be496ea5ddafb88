// glTF 2.0 binary (GLB) output: one node, one mesh, one primitive of indexed triangles with
// positions, normals and, when the mesh has them, texture coordinates (TEXCOORD_0), the generator and version in the asset, and in asset.extras what the
// file promises: the tolerance asked, the proven bound (encoding included) and the source mesh.
// Three encodings (docs/GLB.md): float32 attributes; KHR_mesh_quantization (int16 positions on
// the grid of core/output/position_quantization.h, int8 normals); and that again compressed with
// EXT_meshopt_compression (meshoptimizer), its triangles and vertices reordered for it.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/output/position_quantization.h"
#include "core/mesh/triangle_mesh.h"

namespace tessera {

enum class GlbEncoding : uint8_t { kFloat, kQuantized, kMeshopt };

const char* glbEncodingName(GlbEncoding encoding);
// "float", "quantized" or "meshopt"; throws TesseraError (kInvalidInput) naming the value.
GlbEncoding parseGlbEncoding(const std::string& name);

// What asset.extras states about the mesh.
struct GlbDescription {
  std::string sourceName = {};    // the control mesh (its id, or its file's stem); names node and mesh
  std::string sourceSha256 = {};  // of its canonical encoding (core/mesh/mesh_codec.h); empty: unknown
  std::optional<double> tolerance = {};      // ε asked, model units
  std::optional<double> pixelAccuracy = {};  // or pixels, for a camera
  int uniformLevel = 0;                 // or a uniform level
  double guaranteedBound = 0;           // model units, the encoding's error included
};

struct GlbOptions {
  GlbDescription description = {};
  GlbEncoding encoding = GlbEncoding::kFloat;
  // kQuantized, kMeshopt: the positions' grid; unset keeps float positions (int8 normals still).
  std::optional<PositionQuantization> positions = {};
  // Called between the encoding's steps and slices of them (a million vertices or indices, 512K
  // triangles of meshoptimizer's cache ordering, one codec call on at most 64 MiB), so a caller
  // can abandon a large file by throwing from it.
  std::function<void()> checkpoint = {};
};

// Throws TesseraError (kInvalidInput) for a mesh it cannot write, kLimitExceeded past 4 GiB.
std::vector<uint8_t> writeGlb(const TriangleMesh& mesh, const GlbOptions& options);

}  // namespace tessera
