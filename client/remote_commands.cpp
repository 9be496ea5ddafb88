// Remote commands of the `tessera` CLI: upload, list, get, delete, info and health, each one
// call (or stream) to a tessera-server chosen with --server, and the load tester `bench`
// (client/remote_bench.h). The remote form of `tessellate`
// shares the local command (client/remote_tessellate.h).
#include <fmt/format.h>

#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>

#include "client/commands.h"
#include "client/remote_bench.h"
#include "client/remote_connection.h"
#include "client/remote_progress.h"
#include "client/remote_render.h"
#include "client/remote_mesh_download.h"
#include "client/remote_upload.h"
#include "client/remote_upload_positions.h"
#include "core/base/error.h"
#include "core/mesh/obj_reader.h"
#include "core/mesh/subdivision_rules.h"
#include "grpc/health/v1/health.grpc.pb.h"
#include "tessera/v1/mesh.grpc.pb.h"
#include "tessera/v1/server_info.grpc.pb.h"

namespace tessera::cli {
namespace {

namespace v1 = tessera::v1;

std::string formatTime(const google::protobuf::Timestamp& t) {
  std::time_t seconds = static_cast<std::time_t>(t.seconds());
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

// The stored mesh's rules, named as `tessera inspect` and the upload flags name them.
std::string rulesText(const v1::SubdivisionOptions& o) {
  const BoundaryInterpolation boundary =
      o.boundary_interpolation() == v1::BOUNDARY_INTERPOLATION_EDGE_AND_CORNER
          ? BoundaryInterpolation::kEdgeAndCorner
      : o.boundary_interpolation() == v1::BOUNDARY_INTERPOLATION_NONE
          ? BoundaryInterpolation::kNone
          : BoundaryInterpolation::kEdgeOnly;
  const CreaseMethod creases = o.crease_method() == v1::CREASE_METHOD_CHAIKIN
                                   ? CreaseMethod::kChaikin
                                   : CreaseMethod::kUniform;
  const TriangleSubdivision triangles = o.triangle_subdivision() == v1::TRIANGLE_SUBDIVISION_SMOOTH
                                            ? TriangleSubdivision::kSmooth
                                            : TriangleSubdivision::kCatmark;
  return fmt::format("boundary {}, creases {}, triangles {}", boundaryName(boundary),
                     creaseMethodName(creases), triangleSubdivisionName(triangles));
}

void printMesh(const v1::Mesh& m) {
  const v1::BoundingBox& b = m.bounding_box();
  std::cout << fmt::format(
      "name          {}\ndisplay name  {}\nsource        {} ({})\nvertices      {}\n"
      "faces         {} ({} face vertices)\ncreases       {}\ncorners       {}\nholes         {}\n"
      "rules         {}\nbounding box  ({:g}, {:g}, {:g}) - ({:g}, {:g}, {:g})\n"
      "sha256        {}\nstored        {}\ncreated       {}\n",
      m.name(), m.display_name(), m.source_format() == v1::MESH_FORMAT_OBJ ? "OBJ" : "arrays",
      humanBytes(m.source_bytes()), m.vertex_count(), m.face_count(), m.face_vertex_count(),
      m.crease_count(), m.corner_count(), m.hole_count(), rulesText(m.options()), b.min().x(),
      b.min().y(), b.min().z(), b.max().x(), b.max().y(), b.max().z(), m.sha256(),
      humanBytes(m.stored_bytes()), formatTime(m.create_time()));
}

struct UploadArgs {
  std::string file;
  std::string name;
  std::string displayName;
  std::string boundary, creaseMethod, triangles, uvInterpolation;
  std::string topologyOf;
};

// `upload --topology-of`: the OBJ read here (the flags' rules over its tags), its topology checked
// against the stored mesh's, then only its positions (and UVs that changed) sent.
int runPositionsUpload(const RemoteEndpoint& endpoint, const UploadArgs& args, UploadOptions options) {
  ControlMesh local;
  try {
    local = readObjFile(args.file);
  } catch (const TesseraError& e) {
    std::cerr << "tessera: " << e.what() << "\n";
    return e.kind() == ErrorKind::kLimitExceeded ? kExitLimit
           : e.kind() == ErrorKind::kUnsupported ? kExitUnsupported
                                                 : kExitInvalidInput;
  } catch (const std::exception& e) {  // the file could not be read
    std::cerr << "tessera: " << e.what() << "\n";
    return kExitIo;
  }
  auto stub = v1::MeshService::NewStub(makeChannel(endpoint));
  v1::Mesh stored;
  v1::MeshArrays storedArrays;
  {
    grpc::ClientContext context;
    prepareContext(context, endpoint);
    const grpc::Status status = downloadMesh(*stub, context, options.topologyOf, &stored, &storedArrays);
    if (!status.ok()) return reportRpcError("download " + options.topologyOf + " (--topology-of)", status, &context);
  }
  v1::SubdivisionOptions rules;
  v1::MeshArrays arrays;
  try {
    arrays = positionsOnlyArrays(local, args.file, options.topologyOf, storedArrays, &rules);
  } catch (const TopologyMismatch& e) {
    std::cerr << "tessera: " << e.what() << "\n";
    return kExitInvalidInput;
  }
  // The file's rules unless a flag names one: the server refuses rules other than the stored mesh's.
  const v1::SubdivisionOptions& flags = options.subdivision;
  if (flags.boundary_interpolation() == v1::BOUNDARY_INTERPOLATION_UNSPECIFIED) options.subdivision.set_boundary_interpolation(rules.boundary_interpolation());
  if (flags.crease_method() == v1::CREASE_METHOD_UNSPECIFIED) options.subdivision.set_crease_method(rules.crease_method());
  if (flags.triangle_subdivision() == v1::TRIANGLE_SUBDIVISION_UNSPECIFIED) options.subdivision.set_triangle_subdivision(rules.triangle_subdivision());
  if (flags.uv_interpolation() == v1::UV_INTERPOLATION_UNSPECIFIED) options.subdivision.set_uv_interpolation(rules.uv_interpolation());
  if (options.displayName.empty()) options.displayName = std::filesystem::path(args.file).filename().string();
  grpc::ClientContext context;
  prepareContext(context, endpoint);
  v1::Mesh mesh;
  const grpc::Status status = uploadMeshArrays(*stub, context, arrays, options, &mesh);
  if (!status.ok()) return reportRpcError("upload " + args.file, status, &context);
  printMesh(mesh);
  std::cout << fmt::format("sent          {} (positions{} of {}'s topology)\n", humanBytes(arraysUploadBytes(arrays)),
                           arrays.uvs_size() > 0 ? " and UVs" : "", options.topologyOf);
  return kExitOk;
}

int runUpload(const RemoteEndpoint& endpoint, const UploadArgs& args) {
  UploadOptions options;
  options.meshId = asMeshName(args.name).substr(7);
  options.displayName = args.displayName;
  if (args.boundary == "edge-only") {
    options.subdivision.set_boundary_interpolation(v1::BOUNDARY_INTERPOLATION_EDGE_ONLY);
  } else if (args.boundary == "edge-and-corner") {
    options.subdivision.set_boundary_interpolation(v1::BOUNDARY_INTERPOLATION_EDGE_AND_CORNER);
  } else if (args.boundary == "none") {
    options.subdivision.set_boundary_interpolation(v1::BOUNDARY_INTERPOLATION_NONE);
  }
  if (!args.creaseMethod.empty()) {
    options.subdivision.set_crease_method(
        args.creaseMethod == "chaikin" ? v1::CREASE_METHOD_CHAIKIN : v1::CREASE_METHOD_UNIFORM);
  }
  if (!args.triangles.empty()) {
    options.subdivision.set_triangle_subdivision(args.triangles == "smooth"
                                                     ? v1::TRIANGLE_SUBDIVISION_SMOOTH
                                                     : v1::TRIANGLE_SUBDIVISION_CATMARK);
  }
  if (const std::optional<UvInterpolation> rule = parseUvInterpolation(args.uvInterpolation)) {
    // The proto lists the rules from LINEAR_NONE = 1 in the order UvInterpolation lists them
    // after kAll; LINEAR_ALL is 6.
    options.subdivision.set_uv_interpolation(*rule == UvInterpolation::kAll ? v1::UV_INTERPOLATION_LINEAR_ALL
                                                                            : v1::UvInterpolation(int(*rule)));
  }
  if (!args.topologyOf.empty()) {
    options.topologyOf = asMeshName(args.topologyOf);
    return runPositionsUpload(endpoint, args, options);
  }
  auto stub = v1::MeshService::NewStub(makeChannel(endpoint));
  grpc::ClientContext context;
  prepareContext(context, endpoint);
  v1::Mesh mesh;
  ProgressBar bar("upload");
  grpc::Status status;
  try {
    status =
        uploadObjFile(*stub, context, args.file, options, &mesh, [&](int64_t sent, int64_t total) {
          bar.update(total > 0 ? double(sent) / double(total) : 1.0, humanBytes(sent));
        });
  } catch (const LocalFileError& e) {
    std::cerr << "tessera: " << e.what() << "\n";
    return kExitIo;
  }
  bar.finish();
  if (!status.ok()) return reportRpcError("upload " + args.file, status, &context);
  printMesh(mesh);
  return kExitOk;
}

int runList(const RemoteEndpoint& endpoint, int pageSize) {
  auto stub = v1::MeshService::NewStub(makeChannel(endpoint));
  v1::ListMeshesRequest request;
  request.set_page_size(pageSize);
  std::cout << fmt::format("{:<40} {:>10} {:>10} {:>10}  {}\n", "NAME", "VERTICES", "FACES",
                           "STORED", "CREATED");
  do {
    grpc::ClientContext context;
    prepareContext(context, endpoint, kUnaryTimeout);
    v1::ListMeshesResponse page;
    grpc::Status status = stub->ListMeshes(&context, request, &page);
    if (!status.ok()) return reportRpcError("list", status, &context);
    for (const v1::Mesh& m : page.meshes()) {
      std::cout << fmt::format("{:<40} {:>10} {:>10} {:>10}  {}\n", m.name(), m.vertex_count(),
                               m.face_count(), humanBytes(m.stored_bytes()),
                               formatTime(m.create_time()));
    }
    request.set_page_token(page.next_page_token());
  } while (!request.page_token().empty());
  return kExitOk;
}

int runGet(const RemoteEndpoint& endpoint, const std::string& name) {
  auto stub = v1::MeshService::NewStub(makeChannel(endpoint));
  grpc::ClientContext context;
  prepareContext(context, endpoint, kUnaryTimeout);
  v1::GetMeshRequest request;
  request.set_name(asMeshName(name));
  v1::Mesh mesh;
  grpc::Status status = stub->GetMesh(&context, request, &mesh);
  if (!status.ok()) return reportRpcError("get " + request.name(), status, &context);
  printMesh(mesh);
  return kExitOk;
}

int runDelete(const RemoteEndpoint& endpoint, const std::string& name) {
  auto stub = v1::MeshService::NewStub(makeChannel(endpoint));
  grpc::ClientContext context;
  prepareContext(context, endpoint, kUnaryTimeout);
  v1::DeleteMeshRequest request;
  request.set_name(asMeshName(name));
  google::protobuf::Empty empty;
  grpc::Status status = stub->DeleteMesh(&context, request, &empty);
  if (!status.ok()) return reportRpcError("delete " + request.name(), status, &context);
  std::cout << "deleted " << request.name() << "\n";
  return kExitOk;
}

int runInfo(const RemoteEndpoint& endpoint) {
  auto stub = v1::ServerInfoService::NewStub(makeChannel(endpoint));
  grpc::ClientContext context;
  prepareContext(context, endpoint, kUnaryTimeout);
  v1::ServerInfo info;
  grpc::Status status = stub->GetServerInfo(&context, v1::GetServerInfoRequest(), &info);
  if (!status.ok()) return reportRpcError("info", status, &context);
  std::cout << fmt::format(
      "server        {} (tessera {})\ndevice        {}\nstore         {}\n"
      "auth          {}\ntls           {}\ntessellation  {}\n",
      endpoint.server, info.version(), info.device(), info.store(),
      info.auth_required() ? "bearer token" : "none", info.tls() ? "yes" : "no",
      info.tessellation_available() ? "available" : "not available");
  for (const v1::Backend& b : info.backends()) {
    std::cout << fmt::format("backend       {} ({}): {}\n", b.name(),
                             b.available() ? "available" : "unavailable", b.detail());
  }
  const v1::ServerLimits& l = info.limits();
  std::cout << fmt::format(
      "limits        upload {}, {} vertices, {} faces, face size {}, tolerance >= {:g} x "
      "diagonal,\n"
      "              pixel accuracy >= {:g}, {} triangles, uniform level <= {}, {} pixels,\n"
      "              {} jobs running + {} queued\n",
      humanBytes(l.max_upload_bytes()), l.max_vertices(), l.max_faces(), l.max_face_size(),
      l.min_relative_tolerance(), l.min_pixel_accuracy(), l.max_triangles(), l.max_uniform_level(),
      l.max_image_pixels(), l.max_concurrent_jobs(), l.max_queued_jobs());
  return kExitOk;
}

// For container health checks and scripts: exit code 0 only while the server says SERVING.
int runHealth(const RemoteEndpoint& endpoint) {
  auto stub = grpc::health::v1::Health::NewStub(makeChannel(endpoint));
  grpc::ClientContext context;
  prepareContext(context, endpoint, std::chrono::seconds(5));
  grpc::health::v1::HealthCheckResponse response;
  grpc::Status status = stub->Check(&context, grpc::health::v1::HealthCheckRequest(), &response);
  if (!status.ok()) return reportRpcError("health", status, &context);
  bool serving = response.status() == grpc::health::v1::HealthCheckResponse::SERVING;
  std::cout << grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response.status()) << "\n";
  return serving ? kExitOk : kExitRemote;
}

}  // namespace

void registerRemoteCommands(CLI::App& app, CommandContext& context) {
  // Shared by the callbacks, which run after parsing fills it in.
  auto endpoint = std::make_shared<RemoteEndpoint>();
  addEndpointOptions(app, *endpoint);

  auto upload = std::make_shared<UploadArgs>();
  CLI::App* up = app.add_subcommand("upload", "Upload an OBJ control mesh to the server");
  up->add_option("file", upload->file, "The .obj file")->required()->check(CLI::ExistingFile);
  up->add_option("--name", upload->name, "Mesh id (or meshes/ID) to store it under")->required();
  up->add_option("--display-name", upload->displayName, "Free text (default: the file name)");
  up->add_option("--boundary", upload->boundary, "Boundary interpolation (default: the file's)")
      ->check(CLI::IsMember({"edge-only", "edge-and-corner", "none"}));
  up->add_option("--crease-method", upload->creaseMethod,
                 "Semi-sharp crease rule (default: the file's)")
      ->check(CLI::IsMember({"uniform", "chaikin"}));
  up->add_option("--triangles", upload->triangles, "Triangle rule (default: the file's)")
      ->check(CLI::IsMember({"catmark", "smooth"}));
  up->add_option("--uv-interpolation", upload->uvInterpolation, "How UVs are subdivided (OpenSubdiv's FVAR_LINEAR_*; default all)")
      ->check(CLI::IsMember({"all", "none", "corners-only", "corners-plus1", "corners-plus2", "boundaries"}));
  up->add_option("--topology-of", upload->topologyOf,
                 "A stored mesh (meshes/NAME) whose topology the file shares: its positions (and UVs if "
                 "they changed) are all that is sent, once the file's topology is checked against it");
  up->callback([&context, endpoint, upload] { context.exitCode = runUpload(*endpoint, *upload); });

  auto pageSize = std::make_shared<int>(100);
  CLI::App* list = app.add_subcommand("list", "List the server's meshes");
  list->add_option("--page-size", *pageSize, "Meshes per request")->capture_default_str();
  list->callback(
      [&context, endpoint, pageSize] { context.exitCode = runList(*endpoint, *pageSize); });

  auto getName = std::make_shared<std::string>();
  CLI::App* get = app.add_subcommand("get", "Show a stored mesh's metadata");
  get->add_option("mesh", *getName, "meshes/ID")->required();
  get->callback([&context, endpoint, getName] { context.exitCode = runGet(*endpoint, *getName); });

  auto deleteName = std::make_shared<std::string>();
  CLI::App* del = app.add_subcommand("delete", "Delete a stored mesh");
  del->add_option("mesh", *deleteName, "meshes/ID")->required();
  del->callback(
      [&context, endpoint, deleteName] { context.exitCode = runDelete(*endpoint, *deleteName); });

  CLI::App* info = app.add_subcommand("info", "Show the server's version, backends and limits");
  info->callback([&context, endpoint] { context.exitCode = runInfo(*endpoint); });

  CLI::App* health = app.add_subcommand("health", "Exit 0 if the server reports SERVING");
  health->callback([&context, endpoint] { context.exitCode = runHealth(*endpoint); });

  registerBenchCommand(app, context, endpoint);
  registerRenderCommand(app, context);
}

}  // namespace tessera::cli
