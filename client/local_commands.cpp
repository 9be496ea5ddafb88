// Local commands: run the core in-process on a mesh file.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "client/camera_flags.h"
#include "client/commands.h"
#include "core/base/error.h"
#include "core/base/sha256.h"
#include "core/mesh/mesh_codec.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/glb_output.h"
#include "core/pipeline/mesh_report.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#if TESSERA_WITH_REMOTE
#include "client/remote_tessellate.h"
#endif
#include <chrono>
#include <filesystem>
#include <fstream>

namespace tessera::cli {

int exitCodeFor(const TesseraError& error) {
  switch (error.kind()) {
    case ErrorKind::kInvalidInput:
      return kExitInvalidInput;
    case ErrorKind::kUnsupported:
      return kExitUnsupported;
    case ErrorKind::kLimitExceeded:
      return kExitLimit;
  }
  return kExitInvalidInput;
}

namespace {

template <typename Map>
nlohmann::json histogram(const Map& counts) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, count] : counts) j[std::to_string(key)] = count;
  return j;
}

nlohmann::json toJson(const MeshReport& r) {
  nlohmann::json rings = nlohmann::json::object();
  for (const auto& [kind, byValence] : r.ringsByKind) rings[kind] = histogram(byValence);
  return {
      {"vertices", r.vertices},
      {"unused_vertices", r.unusedVertices},
      {"faces", r.faces},
      {"face_sizes", histogram(r.faceSizes)},
      {"valences", histogram(r.valences)},
      {"edges", r.edges},
      {"boundary_edges", r.boundaryEdges},
      {"non_manifold_edges", r.nonManifoldEdges},
      {"non_manifold_vertices", r.nonManifoldVertices},
      {"creases", r.creases},
      {"infinitely_sharp_creases", r.infiniteCreases},
      {"corners", r.corners},
      {"holes", r.holes},
      {"boundary_interpolation", r.boundaryInterpolation},
      {"crease_method", r.creaseMethod},
      {"triangle_subdivision", r.triangleSubdivision},
      {"regular_patches", r.regularPatches},
      {"rings", rings},
      {"locally_refined_faces", r.locallyRefinedFaces},
      {"isolation_level", r.isolationLevel},
      {"refused", r.refusal.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.refusal)},
  };
}

std::string formatHistogram(const std::map<int, int>& counts) {
  std::string text;
  for (const auto& [key, count] : counts) {
    text += (text.empty() ? "" : ", ") + std::to_string(key) + ": " + std::to_string(count);
  }
  return text.empty() ? "none" : text;
}

void printText(const std::string& path, const MeshReport& r) {
  std::printf("%s\n", path.c_str());
  std::printf("  vertices            %d (%d unused)\n", r.vertices, r.unusedVertices);
  std::printf("  faces               %d  sizes {%s}\n", r.faces,
              formatHistogram(r.faceSizes).c_str());
  std::printf("  valences            {%s}\n", formatHistogram(r.valences).c_str());
  std::printf("  edges               %d (%d on a boundary)\n", r.edges, r.boundaryEdges);
  if (r.nonManifoldEdges > 0 || r.nonManifoldVertices > 0) {
    std::printf("  non-manifold        %d edges, %d vertices (cut into manifold sheets)\n", r.nonManifoldEdges,
                r.nonManifoldVertices);
  }
  std::printf("  creases             %d (%d infinitely sharp), corners %d, holes %d\n", r.creases,
              r.infiniteCreases, r.corners, r.holes);
  std::printf("  rules               boundary %s, creases %s, triangles %s\n",
              r.boundaryInterpolation.c_str(), r.creaseMethod.c_str(),
              r.triangleSubdivision.c_str());
  if (!r.refusal.empty()) {
    std::printf("  refused             %s\n", r.refusal.c_str());
    return;
  }
  std::printf("  regular patches     %d\n", r.regularPatches);
  for (const auto& [kind, byValence] : r.ringsByKind) {
    std::printf("  %-8s rings      {%s} (valence: count)\n", kind.c_str(),
                formatHistogram(byValence).c_str());
  }
  std::printf("  locally refined     %d base faces (isolation level %d)\n", r.locallyRefinedFaces,
              r.isolationLevel);
}

void registerInspect(CLI::App& app, CommandContext& context) {
  auto* command = app.add_subcommand("inspect", "Describe what Tessera sees in a mesh");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  command->add_option("model", *path, "OBJ file (OpenSubdiv tags understood)")->required();
  command->add_flag("--json", *json, "Print the report as JSON");
  command->callback([&context, path, json] {
    try {
      MeshReport report = inspectMesh(readObjFile(*path));
      if (*json) {
        std::cout << toJson(report).dump(2) << "\n";
      } else {
        printText(*path, report);
      }
      context.exitCode = report.refusal.empty() ? kExitOk : kExitUnsupported;
    } catch (const TesseraError& e) {
      std::cerr << "tessera inspect: " << e.what() << "\n";
      context.exitCode = exitCodeFor(e);
    }
  });
}

int runLocalTessellate(const TessellateFlags& flags) {
  auto start = std::chrono::steady_clock::now();
  try {
    TessellationOptions options = flags.toOptions();
    ControlMesh mesh = readObjFile(flags.model);
    PreprocessingOptions preprocessing;
    preprocessing.finestRelativeTolerance = finestRelativeTolerance(mesh, options);
    PatchSet patches = buildPatchSet(mesh, preprocessing);
    double preprocessMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const GlbEncoding encoding = parseGlbEncoding(flags.encoding);
    const std::optional<PositionQuantization> positions =
        reserveForEncoding(encoding, patches, options);
    TessellationResult result = tessellate(patches, mesh, options);
    // Named by the file's stem, as a server names it by the mesh id ("bigguy" for bigguy.obj
    // uploaded as meshes/bigguy), with the SHA-256 the server would give it: the output does not
    // depend on where the input lay, and a local and a remote tessellation of the same mesh are
    // the same bytes.
    const GlbRequest request{encoding, std::filesystem::path(flags.model).stem().string(),
                             sha256Hex(encodeCanonicalMesh(mesh))};
    std::vector<uint8_t> glb =
        writeGlb(result.mesh, glbOptionsFor(request, options, result.summary, positions));
    std::ofstream out(flags.output, std::ios::binary);
    out.write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
    if (!out) {
      std::cerr << "tessera tessellate: cannot write " << flags.output << "\n";
      return kExitIo;
    }
    double totalMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const TessellationSummary& s = result.summary;
    std::printf("triangles        %lld\n", (long long)s.triangles);
    std::printf("patches          %lld (%zu regular, %d rings)\n", (long long)s.pieces,
                patches.regular.size(), s.rings);
    std::printf("ring depth       average %.2f, maximum %d\n", s.averageDepth, s.maxDepth);
    std::printf("guaranteed bound %.6g (tolerance %.6g)\n", s.guaranteedBound, s.tolerance);
    std::printf("time             %.1f ms (preprocess %.1f, plan %.1f, triangulate %.1f)\n",
                totalMs, preprocessMs, s.planMs, s.tessellateMs);
    std::printf("wrote            %s (%zu bytes)\n", flags.output.c_str(), glb.size());
    return kExitOk;
  } catch (const TesseraError& e) {
    std::cerr << "tessera tessellate: " << e.what() << "\n";
    return exitCodeFor(e);
  }
}

}  // namespace

void registerLocalCommands(CLI::App& app, CommandContext& context) {
  registerInspect(app, context);
  auto flags = std::make_shared<TessellateFlags>();
  auto* command = app.add_subcommand("tessellate", "Tessellate a mesh's limit surface to a GLB");
  flags->addTo(*command);
  command->callback([&app, &context, flags] {
#if TESSERA_WITH_REMOTE
    // `meshes/NAME` names a mesh on the server; anything else is a local file.
    if (isRemoteMeshName(flags->model)) {
      context.exitCode = runRemoteTessellate(app, *flags);
      return;
    }
#endif
    context.exitCode = runLocalTessellate(*flags);
  });
}

}  // namespace tessera::cli
