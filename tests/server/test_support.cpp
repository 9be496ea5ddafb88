#include "tests/server/test_support.h"

#include <arpa/inet.h>
#include <grpcpp/generic/generic_stub.h>
#include <fmt/format.h>
#include <libpq-fe.h>
#include <netdb.h>
#include <openssl/evp.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <future>
#include <sstream>
#include <thread>

namespace tessera::test {
namespace {

std::string runAdmin(const std::string& url, const std::string& sql) {
  PGconn* c = PQconnectdb(url.c_str());
  PQsetNoticeProcessor(c, [](void*, const char*) {}, nullptr);  // "does not exist, skipping"
  std::string error;
  if (PQstatus(c) != CONNECTION_OK) {
    error = PQerrorMessage(c);
  } else {
    PGresult* r = PQexec(c, sql.c_str());
    if (PQresultStatus(r) != PGRES_COMMAND_OK) error = PQresultErrorMessage(r);
    PQclear(r);
  }
  PQfinish(c);
  return error;
}

// The URL with its database name replaced: postgresql://user@host:port/DB?options.
std::string withDatabase(const std::string& url, const std::string& database) {
  size_t hostStart = url.find("://");
  size_t pathStart = url.find('/', hostStart == std::string::npos ? 0 : hostStart + 3);
  size_t query = url.find('?');
  std::string base = url.substr(0, std::min(pathStart, query));
  std::string rest = query == std::string::npos ? "" : url.substr(query);
  return base + "/" + database + rest;
}

void appendLe(std::string& out, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((value >> (8 * i)) & 0xff);
}

// Resolves an OBJ index (1-based, or negative from the end) to 0-based.
int32_t objIndex(const std::string& token, size_t vertexCount) {
  int value = std::stoi(token.substr(0, token.find('/')));
  return value < 0 ? static_cast<int32_t>(vertexCount) + value : value - 1;
}

// The vt of an OBJ face token ("v/vt", "v/vt/vn"), 0-based; −1 for none.
int32_t objUvIndex(const std::string& token, size_t uvCount) {
  const size_t slash = token.find('/');
  if (slash == std::string::npos || slash + 1 >= token.size() || token[slash + 1] == '/') return -1;
  int value = std::stoi(token.substr(slash + 1));
  return value < 0 ? static_cast<int32_t>(uvCount) + value : value - 1;
}

}  // namespace

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "tessera-server-test-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::unique_ptr<PostgresDatabase> PostgresDatabase::create(std::string* whyNot) {
  const char* adminUrl = std::getenv(kPostgresUrlVariable);
  if (!adminUrl || !*adminUrl) {
    *whyNot = fmt::format("{} is not set; `tools/pg-test-cluster.sh start` prints a URL for it",
                          kPostgresUrlVariable);
    return nullptr;
  }
  static std::atomic<int> serial{0};
  std::string name = fmt::format("tessera_test_{}_{}", getpid(), serial++);
  std::string error = runAdmin(adminUrl, "CREATE DATABASE " + name);
  if (!error.empty()) {
    *whyNot = fmt::format("cannot create a database on {}: {}", adminUrl, error);
    return nullptr;
  }
  return std::unique_ptr<PostgresDatabase>(
      new PostgresDatabase(adminUrl, name, withDatabase(adminUrl, name)));
}

PostgresDatabase::PostgresDatabase(std::string adminUrl, std::string name, std::string url)
    : adminUrl_(std::move(adminUrl)), name_(std::move(name)), url_(std::move(url)) {}

PostgresDatabase::~PostgresDatabase() {
  // FORCE: a SIGKILLed server may leave a connection the cluster has not noticed yet.
  if (name_.empty()) return;
  runAdmin(adminUrl_, "DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
  runAdmin(adminUrl_, "DROP DATABASE IF EXISTS " + name_ + "_away WITH (FORCE)");  // a test that failed mid-outage
}

std::string PostgresDatabase::takeAway() {
  // The terminated sessions leave asynchronously, and the server reconnects between probes:
  // the rename is retried until no session holds the database.
  std::string error;
  for (int attempt = 0; attempt < 50; ++attempt) {
    error = runAdmin(adminUrl_, fmt::format("DO $$BEGIN PERFORM pg_terminate_backend(pid) FROM pg_stat_activity "
                                            "WHERE datname = '{0}'; END$$; ALTER DATABASE {0} RENAME TO {0}_away",
                                            name_));
    if (error.empty()) return error;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return error;
}

std::vector<int> PostgresDatabase::sessions() const {
  std::vector<int> pids;
  PGconn* c = PQconnectdb(adminUrl_.c_str());
  if (PQstatus(c) == CONNECTION_OK) {
    const std::string sql = fmt::format("SELECT pid FROM pg_stat_activity WHERE datname = '{}'", name_);
    PGresult* r = PQexec(c, sql.c_str());
    if (PQresultStatus(r) == PGRES_TUPLES_OK) {
      for (int row = 0; row < PQntuples(r); ++row) pids.push_back(std::atoi(PQgetvalue(r, row, 0)));
    }
    PQclear(r);
  }
  PQfinish(c);
  return pids;
}

std::string PostgresDatabase::giveBack() {
  return runAdmin(adminUrl_, fmt::format("ALTER DATABASE {0}_away RENAME TO {0}", name_));
}

bool MeshArrays::operator==(const MeshArrays& o) const {
  auto sameCreases = [&] {
    if (creases.size() != o.creases.size()) return false;
    for (size_t i = 0; i < creases.size(); ++i) {
      if (creases[i].v0 != o.creases[i].v0 || creases[i].v1 != o.creases[i].v1 ||
          std::bit_cast<uint32_t>(creases[i].sharpness) != std::bit_cast<uint32_t>(o.creases[i].sharpness))
        return false;
    }
    return true;
  };
  auto sameCorners = [&] {
    if (corners.size() != o.corners.size()) return false;
    for (size_t i = 0; i < corners.size(); ++i) {
      if (corners[i].vertex != o.corners[i].vertex ||
          std::bit_cast<uint32_t>(corners[i].sharpness) != std::bit_cast<uint32_t>(o.corners[i].sharpness))
        return false;
    }
    return true;
  };
  // Positions compare bit for bit: "intact" means byte-equal, not nearly equal.
  auto samePositions = [&] {
    if (positions.size() != o.positions.size()) return false;
    for (size_t i = 0; i < positions.size(); ++i) {
      if (std::bit_cast<uint32_t>(positions[i]) != std::bit_cast<uint32_t>(o.positions[i])) return false;
    }
    return true;
  };
  auto sameUvs = [&] {
    if (uvs.size() != o.uvs.size()) return false;
    for (size_t i = 0; i < uvs.size(); ++i) {
      if (std::bit_cast<uint32_t>(uvs[i]) != std::bit_cast<uint32_t>(o.uvs[i])) return false;
    }
    return uvIndices == o.uvIndices && origin == o.origin;
  };
  return samePositions() && faceSizes == o.faceSizes && faceVertices == o.faceVertices &&
         sameCreases() && sameCorners() && holes == o.holes && sameUvs();
}

int64_t MeshArrays::uploadBytes() const {
  return 4 * static_cast<int64_t>(positions.size() + faceSizes.size() + faceVertices.size() +
                                  holes.size() + uvs.size() + uvIndices.size()) +
         (origin[0] != 0 || origin[1] != 0 || origin[2] != 0 ? 24 : 0) +
         12 * static_cast<int64_t>(creases.size()) + 8 * static_cast<int64_t>(corners.size());
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::filesystem::path modelPath(const std::string& name) {
  return std::filesystem::path(TESSERA_MODELS_DIR) / name;
}

MeshArrays parseObjVerticesAndFaces(const std::string& text) {
  MeshArrays mesh;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "v") {
      float x, y, z;
      words >> x >> y >> z;
      mesh.positions.insert(mesh.positions.end(), {x, y, z});
    } else if (kind == "vt") {
      float u = 0, v = 0;
      words >> u >> v;
      mesh.uvs.insert(mesh.uvs.end(), {u, v});
    } else if (kind == "f") {
      int32_t size = 0;
      for (std::string token; words >> token; ++size) {
        mesh.faceVertices.push_back(objIndex(token, mesh.vertexCount()));
        const int32_t uv = objUvIndex(token, mesh.uvs.size() / 2);
        if (uv >= 0) mesh.uvIndices.push_back(uv);
      }
      mesh.faceSizes.push_back(size);
    }
  }
  if (mesh.uvIndices.empty()) mesh.uvs.clear();  // vt no face uses carries nothing
  return mesh;
}

MeshArrays gridMesh(int n, int seed) {
  MeshArrays mesh;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      float height = 0.25f * std::sin(0.7f * i + 1.3f * j + 0.37f * seed);
      mesh.positions.insert(mesh.positions.end(), {float(i), float(j), height});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      int32_t v = j * (n + 1) + i;
      mesh.faceSizes.push_back(4);
      mesh.faceVertices.insert(mesh.faceVertices.end(), {v, v + 1, v + n + 2, v + n + 1});
    }
  }
  return mesh;
}

std::string canonicalEncoding(const MeshArrays& m, uint32_t rules) {
  std::string out = "TSM1";
  appendLe(out, rules, 4);
  appendLe(out, m.vertexCount(), 8);
  for (float f : m.positions) appendLe(out, std::bit_cast<uint32_t>(f), 4);
  appendLe(out, m.faceSizes.size(), 8);
  for (int32_t n : m.faceSizes) appendLe(out, static_cast<uint32_t>(n), 4);
  appendLe(out, m.faceVertices.size(), 8);
  for (int32_t v : m.faceVertices) appendLe(out, static_cast<uint32_t>(v), 4);
  appendLe(out, m.creases.size(), 8);
  for (const auto& c : m.creases) {
    appendLe(out, static_cast<uint32_t>(c.v0), 4);
    appendLe(out, static_cast<uint32_t>(c.v1), 4);
    appendLe(out, std::bit_cast<uint32_t>(c.sharpness), 4);
  }
  appendLe(out, m.corners.size(), 8);
  for (const auto& c : m.corners) {
    appendLe(out, static_cast<uint32_t>(c.vertex), 4);
    appendLe(out, std::bit_cast<uint32_t>(c.sharpness), 4);
  }
  appendLe(out, m.holes.size(), 8);
  for (int32_t h : m.holes) appendLe(out, static_cast<uint32_t>(h), 4);
  if (!m.uvIndices.empty()) {  // only a mesh with UVs has them (mesh.proto)
    out += "UVS1";
    appendLe(out, m.uvs.size(), 8);
    for (float f : m.uvs) appendLe(out, std::bit_cast<uint32_t>(f), 4);
    appendLe(out, m.uvIndices.size(), 8);
    for (int32_t i : m.uvIndices) appendLe(out, static_cast<uint32_t>(i), 4);
  }
  if (m.origin[0] != 0 || m.origin[1] != 0 || m.origin[2] != 0) {  // only a mesh far from the origin
    out += "ORG1";
    for (double c : m.origin) appendLe(out, std::bit_cast<uint64_t>(c), 8);
  }
  return out;
}

std::string sha256Hex(const std::string& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr);
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

void prepare(grpc::ClientContext& context, const std::string& token, int seconds) {
  if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(seconds));
}

UploadResult uploadMessages(v1::MeshService::Stub& stub,
                            const std::vector<v1::UploadMeshRequest>& messages,
                            const std::string& token) {
  UploadResult result;
  grpc::ClientContext context;
  prepare(context, token);
  auto writer = stub.UploadMesh(&context, &result.mesh);
  for (const auto& message : messages) {
    if (!writer->Write(message)) break;  // the server has answered already
  }
  writer->WritesDone();
  result.status = writer->Finish();
  return result;
}

v1::UploadMeshRequest headerMessage(const std::string& id, v1::MeshFormat format, int64_t totalBytes,
                                    const std::string& displayName) {
  v1::UploadMeshRequest message;
  v1::UploadMeshHeader* header = message.mutable_header();
  header->set_mesh_id(id);
  header->set_display_name(displayName);
  header->set_format(format);
  header->set_total_bytes(totalBytes);
  return message;
}

std::vector<v1::UploadMeshRequest> arraysUpload(const std::string& id, const MeshArrays& mesh,
                                                size_t floatsPerChunk) {
  std::vector<v1::UploadMeshRequest> messages{
      headerMessage(id, v1::MESH_FORMAT_ARRAYS, mesh.uploadBytes())};
  for (size_t begin = 0; begin < mesh.positions.size(); begin += floatsPerChunk) {
    v1::UploadMeshRequest chunk;
    size_t end = std::min(begin + floatsPerChunk, mesh.positions.size());
    for (size_t i = begin; i < end; ++i) chunk.mutable_arrays()->add_positions(mesh.positions[i]);
    messages.push_back(chunk);
  }
  v1::UploadMeshRequest rest;
  v1::MeshArrays* a = rest.mutable_arrays();
  for (int32_t n : mesh.faceSizes) a->add_face_sizes(n);
  for (int32_t v : mesh.faceVertices) a->add_face_vertices(v);
  for (const auto& c : mesh.creases) {
    v1::Crease* crease = a->add_creases();
    crease->set_v0(c.v0), crease->set_v1(c.v1), crease->set_sharpness(c.sharpness);
  }
  for (const auto& c : mesh.corners) {
    v1::Corner* corner = a->add_corners();
    corner->set_vertex(c.vertex), corner->set_sharpness(c.sharpness);
  }
  for (int32_t h : mesh.holes) a->add_holes(h);
  for (float c : mesh.uvs) a->add_uvs(c);
  for (int32_t i : mesh.uvIndices) a->add_uv_indices(i);
  if (mesh.origin[0] != 0 || mesh.origin[1] != 0 || mesh.origin[2] != 0) {
    a->mutable_origin()->set_x(mesh.origin[0]), a->mutable_origin()->set_y(mesh.origin[1]);
    a->mutable_origin()->set_z(mesh.origin[2]);
  }
  messages.push_back(rest);
  return messages;
}

std::vector<v1::UploadMeshRequest> objUpload(const std::string& id, const std::string& text,
                                             size_t bytesPerChunk, const std::string& displayName) {
  std::vector<v1::UploadMeshRequest> messages{
      headerMessage(id, v1::MESH_FORMAT_OBJ, static_cast<int64_t>(text.size()), displayName)};
  for (size_t begin = 0; begin < text.size(); begin += bytesPerChunk) {
    v1::UploadMeshRequest chunk;
    chunk.set_obj_data(text.substr(begin, bytesPerChunk));
    messages.push_back(chunk);
  }
  return messages;
}

UploadResult uploadModel(v1::MeshService::Stub& stub, const std::string& name) {
  return uploadMessages(stub, objUpload(name, readFile(modelPath(name + ".obj"))));
}

MeshArrays downloadMesh(v1::MeshService::Stub& stub, const std::string& id, grpc::Status* status,
                        v1::Mesh* metadata) {
  grpc::ClientContext context;
  prepare(context);
  v1::DownloadMeshRequest request;
  request.set_name("meshes/" + id);
  auto reader = stub.DownloadMesh(&context, request);
  MeshArrays mesh;
  v1::DownloadMeshResponse message;
  while (reader->Read(&message)) {
    if (message.has_mesh() && metadata) *metadata = message.mesh();
    const v1::MeshArrays& a = message.arrays();
    mesh.positions.insert(mesh.positions.end(), a.positions().begin(), a.positions().end());
    mesh.faceSizes.insert(mesh.faceSizes.end(), a.face_sizes().begin(), a.face_sizes().end());
    mesh.faceVertices.insert(mesh.faceVertices.end(), a.face_vertices().begin(),
                             a.face_vertices().end());
    for (const auto& c : a.creases()) mesh.creases.push_back({c.v0(), c.v1(), c.sharpness()});
    for (const auto& c : a.corners()) mesh.corners.push_back({c.vertex(), c.sharpness()});
    mesh.holes.insert(mesh.holes.end(), a.holes().begin(), a.holes().end());
    mesh.uvs.insert(mesh.uvs.end(), a.uvs().begin(), a.uvs().end());
    mesh.uvIndices.insert(mesh.uvIndices.end(), a.uv_indices().begin(), a.uv_indices().end());
    if (a.has_origin()) mesh.origin = {a.origin().x(), a.origin().y(), a.origin().z()};
  }
  *status = reader->Finish();
  return mesh;
}

double seriesValue(const std::string& page, const std::string& series) {
  const size_t at = page.find("\n" + series + " ");
  if (at == std::string::npos) return -1;
  return std::stod(page.substr(at + series.size() + 2));
}

Streamed tessellateOverGrpc(v1::TessellationService::Stub& stub,
                            const v1::TessellateRequest& request) {
  Streamed result;
  grpc::ClientContext context;
  prepare(context, {}, 120);
  auto reader = stub.Tessellate(&context, request);
  v1::TessellateResponse message;
  while (reader->Read(&message)) {
    if (message.has_glb_chunk()) {
      if (message.glb_chunk().offset() != int64_t(result.glb.size())) {
        result.problem = "a chunk out of order";
      }
      result.glb += message.glb_chunk().data();
    } else if (message.has_summary()) {
      result.summary = message.summary();
    }
  }
  result.status = reader->Finish();
  if (!result.summary) {
    result.problem = "no summary";
  } else if (result.summary->glb_size() != int64_t(result.glb.size())) {
    result.problem = "the GLB's size differs from the summary's";
  } else if (result.summary->glb_sha256() != sha256Hex(result.glb)) {
    result.problem = "the GLB's SHA-256 differs from the summary's";
  }
  return result;
}

std::string httpGet(const std::string& address, const std::string& path) {
  size_t colon = address.rfind(':');
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(address.substr(0, colon).c_str(), address.substr(colon + 1).c_str(), &hints,
                  &found) != 0) {
    return "";
  }
  int fd = socket(found->ai_family, SOCK_STREAM, 0);
  bool connected = fd >= 0 && connect(fd, found->ai_addr, found->ai_addrlen) == 0;
  freeaddrinfo(found);
  std::string response;
  if (connected) {
    std::string request = "GET " + path + " HTTP/1.1\r\nHost: test\r\nConnection: close\r\n\r\n";
    if (send(fd, request.data(), request.size(), MSG_NOSIGNAL) == ssize_t(request.size())) {
      char buffer[4096];
      for (ssize_t n; (n = recv(fd, buffer, sizeof buffer, 0)) > 0;) response.append(buffer, n);
    }
  }
  if (fd >= 0) close(fd);
  return response;
}

std::pair<int, std::string> failedStart(const std::filesystem::path& dir, const std::string& args) {
  std::filesystem::path out = dir / "out.txt";
  std::string command = std::string(TESSERA_SERVER_BINARY) + " --listen 127.0.0.1:0 " +
                        "--metrics-listen off " + args + " > " + out.string() + " 2>&1";
  int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(out)};
}

grpc::Status rawUnaryCall(const std::shared_ptr<grpc::Channel>& channel, const std::string& method,
                          const std::string& request, const std::string& token, std::string* answer) {
  grpc::GenericStub stub(channel);
  grpc::ClientContext context;
  prepare(context, token);
  grpc::Slice slice(request);
  const grpc::ByteBuffer send(&slice, 1);
  grpc::ByteBuffer received;
  std::promise<grpc::Status> done;
  stub.UnaryCall(&context, method, {}, &send, &received, [&done](grpc::Status status) { done.set_value(std::move(status)); });
  const grpc::Status status = done.get_future().get();
  std::vector<grpc::Slice> slices;
  if (answer != nullptr && status.ok() && received.Dump(&slices).ok()) {
    answer->clear();
    for (const grpc::Slice& part : slices) answer->append(reinterpret_cast<const char*>(part.begin()), part.size());
  }
  return status;
}

}  // namespace tessera::test
