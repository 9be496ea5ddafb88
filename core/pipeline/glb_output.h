// One request's GLB: which encoding it asked for, what that encoding costs in ε, and what the
// file then says about itself. Positions are quantized when the grid's error is at most
// kQuantizationShare of the smallest ε the request can have; the planner then works to ε less
// that error everywhere, so the bound the file states still holds (docs/GLB.md).
#pragma once

#include <optional>
#include <string>

#include "core/output/glb_writer.h"
#include "core/pipeline/tessellate.h"
#include "core/rings/patch_set.h"

namespace tessera {

inline constexpr double kQuantizationShare = 0.125;

struct GlbRequest {
  GlbEncoding encoding = GlbEncoding::kFloat;
  std::string sourceName;    // the mesh's id, or its file's stem
  std::string sourceSha256;  // of its canonical encoding (core/mesh/mesh_codec.h)
};

// Sets options.encodingReserve to the grid's error and returns the grid when the encoding
// quantizes and ε leaves room; float positions otherwise (kMeshopt still compresses them). For
// kQuantized without room: TesseraError (kInvalidInput) naming both figures.
std::optional<PositionQuantization> reserveForEncoding(GlbEncoding encoding,
                                                       const PatchSet& patches,
                                                       TessellationOptions& options);

GlbOptions glbOptionsFor(const GlbRequest& request, const TessellationOptions& options,
                         const TessellationSummary& summary,
                         const std::optional<PositionQuantization>& positions);

}  // namespace tessera
