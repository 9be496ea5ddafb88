// Durability: SIGKILL the server while clients stream uploads, restart it on the same store, and
// check that every acknowledged mesh is there bit for bit and that nothing half-written is
// visible. Runs on each store backend.
#include <gtest/gtest.h>

#include <condition_variable>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "tests/server/store_fixture.h"

namespace tessera::test {
namespace {

constexpr int kUploaders = 3;
// Acknowledged uploads to wait for before the kill: enough that the kill lands among many
// in-flight streams and commits.
constexpr int kAcknowledgedBeforeKill = 24;

using CrashRecoveryTest = StoreTest;

std::string meshIdFor(int uploader, int serial) {
  return "crash-" + std::to_string(uploader) + "-" + std::to_string(serial);
}

// Every mesh an uploader may send; sizes vary so that streams end at different moments.
MeshArrays meshFor(int uploader, int serial) {
  return gridMesh(20 + (uploader * 7 + serial * 5) % 40, uploader * 1000 + serial);
}

struct Ledger {
  std::mutex mutex;
  std::condition_variable changed;
  std::map<std::string, std::string> acknowledged;  // id -> sha256 the server returned
  bool stop = false;
};

void uploadUntilStopped(std::shared_ptr<grpc::Channel> channel, int uploader, Ledger& ledger) {
  auto stub = v1::MeshService::NewStub(channel);
  for (int serial = 0;; ++serial) {
    {
      std::lock_guard lock(ledger.mutex);
      if (ledger.stop) return;
    }
    // Small chunks: each upload is a stream of many messages, so the kill can land mid-stream.
    UploadResult result =
        uploadMessages(*stub, arraysUpload(meshIdFor(uploader, serial), meshFor(uploader, serial), 600));
    if (!result.status.ok()) return;  // the server is gone
    std::lock_guard lock(ledger.mutex);
    ledger.acknowledged[meshIdFor(uploader, serial)] = result.mesh.sha256();
    ledger.changed.notify_all();
  }
}

std::vector<v1::Mesh> listAll(v1::MeshService::Stub& stub) {
  std::vector<v1::Mesh> all;
  v1::ListMeshesRequest request;
  request.set_page_size(7);
  do {
    grpc::ClientContext context;
    prepare(context);
    v1::ListMeshesResponse page;
    grpc::Status status = stub.ListMeshes(&context, request, &page);
    EXPECT_TRUE(status.ok()) << status.error_message();
    if (!status.ok()) break;
    all.insert(all.end(), page.meshes().begin(), page.meshes().end());
    request.set_page_token(page.next_page_token());
  } while (!request.page_token().empty());
  return all;
}

// "crash-U-S" -> (U, S).
std::pair<int, int> parseId(const std::string& id) {
  size_t dash = id.rfind('-');
  return {std::stoi(id.substr(6, dash - 6)), std::stoi(id.substr(dash + 1))};
}

TEST_P(CrashRecoveryTest, EveryAcknowledgedUploadSurvivesSigkillAndNoPartialMeshAppears) {
  auto server = startServer();
  ASSERT_TRUE(server);
  Ledger ledger;
  std::vector<std::thread> uploaders;
  for (int u = 0; u < kUploaders; ++u) {
    uploaders.emplace_back(uploadUntilStopped, server->channel(), u, std::ref(ledger));
  }
  {
    std::unique_lock lock(ledger.mutex);
    ledger.changed.wait(lock, [&] {
      return static_cast<int>(ledger.acknowledged.size()) >= kAcknowledgedBeforeKill;
    });
  }
  server->kill9();
  {
    std::lock_guard lock(ledger.mutex);
    ledger.stop = true;
  }
  for (auto& t : uploaders) t.join();

  auto restarted = startServer();
  ASSERT_TRUE(restarted);
  auto stub = v1::MeshService::NewStub(restarted->channel());
  std::set<std::string> listed;
  for (const v1::Mesh& mesh : listAll(*stub)) {
    std::string id = mesh.name().substr(7);
    listed.insert(id);
    auto [uploader, serial] = parseId(id);
    // Listed means complete: content and checksum are those of the mesh that was sent.
    MeshArrays expected = meshFor(uploader, serial);
    grpc::Status status;
    v1::Mesh metadata;
    EXPECT_EQ(downloadMesh(*stub, id, &status, &metadata), expected) << id;
    EXPECT_TRUE(status.ok()) << id << ": " << status.error_message();
    EXPECT_EQ(mesh.sha256(), sha256Hex(canonicalEncoding(expected))) << id;
  }
  for (const auto& [id, sha] : ledger.acknowledged) {
    EXPECT_TRUE(listed.count(id)) << "acknowledged mesh " << id << " was lost";
  }
  // At most one upload per uploader was in flight at the kill; it may or may not have committed.
  EXPECT_LE(listed.size(), ledger.acknowledged.size() + kUploaders);
}

TESSERA_INSTANTIATE_STORE_TESTS(CrashRecoveryTest);

}  // namespace
}  // namespace tessera::test
