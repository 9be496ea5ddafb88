// What the server tests share: temporary folders, a PostgreSQL database per test, mesh fixtures
// built independently of the server's code (an OBJ reader for v/f lines, grids, the canonical
// encoding as mesh.proto documents it), and raw gRPC helpers that send exactly the messages a
// test chooses, malformed ones included.
#pragma once

#include <grpcpp/grpcpp.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <array>
#include <string>
#include <vector>

#include "tessera/v1/mesh.grpc.pb.h"
#include "tessera/v1/server_info.grpc.pb.h"
#include "tessera/v1/tessellation.grpc.pb.h"

namespace tessera::test {

namespace v1 = tessera::v1;

// A folder under /tmp removed with everything in it when the object goes.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A PostgreSQL database of its own for one test, created on the cluster named by
// TESSERA_TEST_POSTGRES_URL and dropped afterwards.
class PostgresDatabase {
 public:
  // Null (with the reason in *whyNot) when the variable is unset or the cluster unreachable.
  static std::unique_ptr<PostgresDatabase> create(std::string* whyNot);
  PostgresDatabase(const PostgresDatabase&) = delete;
  PostgresDatabase& operator=(const PostgresDatabase&) = delete;
  ~PostgresDatabase();
  const std::string& url() const { return url_; }
  // A store outage as its clients see it: every connection to the database ended and its name
  // changed, so that none can reconnect; giveBack() restores the name. Each returns the error,
  // empty on success.
  std::string takeAway();
  std::string giveBack();
  // The process ids of the sessions connected to the database (its server-side backends).
  std::vector<int> sessions() const;

 private:
  PostgresDatabase(std::string adminUrl, std::string name, std::string url);
  std::string adminUrl_, name_, url_;
};

inline constexpr const char* kPostgresUrlVariable = "TESSERA_TEST_POSTGRES_URL";

// A control mesh as plain arrays, the way a client holds one.
struct MeshArrays {
  std::vector<float> positions;
  std::vector<int32_t> faceSizes;
  std::vector<int32_t> faceVertices;
  struct Crease { int32_t v0, v1; float sharpness; };
  struct Corner { int32_t vertex; float sharpness; };
  std::vector<Crease> creases;
  std::vector<Corner> corners;
  std::vector<int32_t> holes;
  std::vector<float> uvs;          // u, v per UV (OBJ vt)
  std::vector<int32_t> uvIndices;  // per face corner, or empty
  std::array<double, 3> origin{0, 0, 0};  // what positions are relative to

  bool operator==(const MeshArrays& other) const;
  size_t vertexCount() const { return positions.size() / 3; }
  // Bytes an ARRAYS upload declares in total_bytes (mesh.proto's rule).
  int64_t uploadBytes() const;
};

std::string readFile(const std::filesystem::path& path);
// A unary call of `method` ("/package.Service/Method") with `request` as its raw message bytes,
// for requests the generated stubs cannot make (hand-encoded or broken messages, unknown
// methods); the answer's bytes go to `answer` when given.
grpc::Status rawUnaryCall(const std::shared_ptr<grpc::Channel>& channel, const std::string& method,
                          const std::string& request, const std::string& token = {}, std::string* answer = nullptr);
// Runs the server with args expecting it to refuse to start; returns its exit status and output.
std::pair<int, std::string> failedStart(const std::filesystem::path& dir, const std::string& args);
std::filesystem::path modelPath(const std::string& name);

// Reads "v x y z" and "f a b c ..." (a, a/t, a//n, a/t/n; 1-based or negative) lines only.
MeshArrays parseObjVerticesAndFaces(const std::string& text);
// An n x n grid of quads whose heights depend on seed, so that meshes differ in content.
MeshArrays gridMesh(int n, int seed);

// The canonical encoding exactly as tessera.v1.Mesh.sha256 documents it, with its rules number.
std::string canonicalEncoding(const MeshArrays& mesh, uint32_t rules = 1);
std::string sha256Hex(const std::string& bytes);

// Adds the bearer token (if any) and a deadline of `seconds` to context.
void prepare(grpc::ClientContext& context, const std::string& token = {}, int seconds = 30);

struct UploadResult {
  grpc::Status status;
  v1::Mesh mesh;
};

// Sends exactly these messages, then half-closes and waits for the answer.
UploadResult uploadMessages(v1::MeshService::Stub& stub,
                            const std::vector<v1::UploadMeshRequest>& messages,
                            const std::string& token = {});
v1::UploadMeshRequest headerMessage(const std::string& id, v1::MeshFormat format, int64_t totalBytes,
                                    const std::string& displayName = {});
// The messages of an ARRAYS upload with positions split every floatsPerChunk floats (so chunks
// may end inside a vertex) and the other arrays in a following message.
std::vector<v1::UploadMeshRequest> arraysUpload(const std::string& id, const MeshArrays& mesh,
                                                size_t floatsPerChunk = 3000);
std::vector<v1::UploadMeshRequest> objUpload(const std::string& id, const std::string& text,
                                             size_t bytesPerChunk = 64 * 1024,
                                             const std::string& displayName = {});

// Uploads the model ../shared/models/<name>.obj as meshes/<name>.
UploadResult uploadModel(v1::MeshService::Stub& stub, const std::string& name);

// Downloads meshes/<id> and reassembles its arrays; the status of the call in *status.
MeshArrays downloadMesh(v1::MeshService::Stub& stub, const std::string& id, grpc::Status* status,
                        v1::Mesh* metadata = nullptr);

// GET http://address/path; the whole response (head and body), or "" on failure.
std::string httpGet(const std::string& address, const std::string& path);

// The value of one series (its name and labels exactly as exposed) in a /metrics page, or -1.
double seriesValue(const std::string& page, const std::string& series);

// A Tessellate stream reassembled; problem says why it is unusable, if it is (chunks out of
// order, no summary, a GLB whose size or SHA-256 differs from the summary's).
struct Streamed {
  grpc::Status status;
  std::string glb;
  std::optional<v1::TessellationSummary> summary;
  std::string problem;
};
Streamed tessellateOverGrpc(v1::TessellationService::Stub& stub, const v1::TessellateRequest& request);

}  // namespace tessera::test
