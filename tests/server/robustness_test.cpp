// Randomly damaged uploads (seeded, so every run sends the same ones): whatever arrives, the
// server answers with a client-error status, never an internal error, and keeps serving.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <set>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

constexpr int kRounds = 150;

// Statuses a damaged upload may get: each says the input was refused or taken.
const std::set<grpc::StatusCode> kAcceptable = {
    grpc::StatusCode::OK, grpc::StatusCode::INVALID_ARGUMENT, grpc::StatusCode::UNIMPLEMENTED,
    grpc::StatusCode::RESOURCE_EXHAUSTED, grpc::StatusCode::ALREADY_EXISTS};

// One or two plausible-looking mistakes per mesh, so that uploads get past the first checks and
// reach the deeper ones (topology, tags, manifoldness) as well.
MeshArrays damagedArrays(std::mt19937& random) {
  MeshArrays mesh = gridMesh(3, 0);
  auto pick = [&](int n) { return static_cast<int32_t>(random() % n); };
  for (int damage = 0, count = 1 + pick(2); damage < count; ++damage) {
    switch (pick(7)) {
      case 0: mesh.faceVertices[pick(36)] = pick(20) - 2; break;
      case 1: mesh.positions[pick(48)] = std::bit_cast<float>(uint32_t(random())); break;
      case 2: mesh.faceSizes[pick(9)] = 3 + pick(3); break;
      case 3: mesh.creases.push_back({pick(18), pick(18), float(pick(12))}); break;
      case 4: mesh.holes.push_back(pick(11) - 1); break;
      case 5: mesh.corners.push_back({pick(18) - 1, float(pick(12)) - 1}); break;
      case 6: std::swap(mesh.faceVertices[pick(36)], mesh.faceVertices[pick(36)]); break;
    }
  }
  return mesh;
}

// A few bytes changed and, sometimes, the end cut off.
std::string damagedObj(std::mt19937& random, const std::string& original) {
  std::string text = original;
  for (int flip = 0, count = random() % 3; flip < count; ++flip) {
    text[random() % text.size()] = static_cast<char>(random());
  }
  return random() % 4 == 0 ? text.substr(0, random() % (text.size() + 1)) : text;
}

TEST(Robustness, RandomlyDamagedUploadsGetClientErrorsAndTheServerKeepsServing) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  std::mt19937 random(20240611);
  const std::string obj = readFile(modelPath("opensubdiv-shapes/catmark_cube_creases1.obj"));
  for (int round = 0; round < kRounds; ++round) {
    std::string id = "fuzz-" + std::to_string(round);
    auto messages = round % 2 ? arraysUpload(id, damagedArrays(random), 7)
                              : objUpload(id, damagedObj(random, obj), 97);
    grpc::Status status = uploadMessages(*stub, messages).status;
    EXPECT_TRUE(kAcceptable.count(status.error_code()))
        << "round " << round << ": " << int(status.error_code()) << " " << status.error_message();
  }
  ASSERT_TRUE(server->running());
  auto fresh = v1::MeshService::NewStub(server->channel());
  EXPECT_TRUE(uploadMessages(*fresh, arraysUpload("after-fuzz", gridMesh(3, 1))).status.ok());
}

}  // namespace
}  // namespace tessera::test
