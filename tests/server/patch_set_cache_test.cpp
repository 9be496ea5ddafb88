// The patch-set cache (server/meshes/patch_set_cache.h) keys preprocessing by content and builds
// each key once at a time. In process, with real preprocessing and tokens the tests hold: the same
// content in another mesh is a hit; concurrent cold gets build once, charging only the builder's
// memory; a cancelled builder leaves the build to a waiter; a waiter whose call is cancelled
// stops at once; the mesh's own failure reaches every waiter; an edit reuses its topology. Over the network, on the real
// server: one content under two ids is decoded and preprocessed once and tessellates to the same
// GLB, and concurrent cold tessellations of one mesh preprocess it once (tessera_patch_cache_*
// and tessera_cache_bytes metrics).
#include "server/meshes/patch_set_cache.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <future>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/sha256.h"
#include "core/mesh/control_mesh.h"
#include "core/mesh/mesh_codec.h"
#include "core/pipeline/preprocessing.h"
#include "tests/server/gate.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;

constexpr size_t kBudget = 256 << 20;
constexpr int64_t kNoLimit = 0;

// A cube scaled by `size`: eight valence-3 vertices, so rings as well as patches.
ControlMesh cube(float size = 1.0f) {
  ControlMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.positions.push_back({size * (i & 1), size * (i >> 1 & 1), size * (i >> 2 & 1)});
  mesh.faceVertices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  mesh.faceSizes.assign(6, 4);
  return mesh;
}

std::string contentSha256(const ControlMesh& mesh) {
  return sha256Hex(encodeCanonicalMesh(mesh));
}

using test::Gate;

// A waiter's token: polled only while the call waits for another's build, it opens `waiting` then.
CancellationToken waiterToken(Gate& waiting, const std::atomic<bool>* cancelled = nullptr) {
  return CancellationToken([&waiting, cancelled] {
    waiting.open();
    return cancelled && cancelled->load();
  });
}

// A builder's token: preprocessing polls it from its first step; the first poll opens `started`
// and holds the build until `go` opens, after which the token fires if `cancelAfter`.
CancellationToken builderToken(Gate& started, Gate& go, bool cancelAfter) {
  return CancellationToken([&started, &go, cancelAfter] {
    started.open();
    EXPECT_TRUE(go.wait());
    return cancelAfter;
  });
}

// What a job reserved, as admission control would have been asked.
class RecordedReservation : public MemoryReservation {
 public:
  void reserve(int64_t bytes, std::string_view) override { reserved += bytes; }
  void release(int64_t bytes) override { reserved -= bytes; }
  std::atomic<int64_t> reserved{0};
};

TEST(PatchSetCache, TheSameContentInAnotherMeshIsPreprocessedOnce) {
  PatchSetCache cache(kBudget, kNoLimit);
  const ControlMesh first = cube(), second = cube();  // two meshes, one content
  ASSERT_EQ(contentSha256(first), contentSha256(second));
  auto built = cache.get(first, contentSha256(first), {}, nullptr);
  auto found = cache.get(second, contentSha256(second), {}, nullptr);
  EXPECT_EQ(found, built);
  EXPECT_EQ(cache.stats().misses, 1u);
  EXPECT_EQ(cache.stats().hits, 1u);

  const ControlMesh other = cube(2.0f);
  EXPECT_NE(cache.get(other, contentSha256(other), {}, nullptr), built);
  EXPECT_EQ(cache.stats().misses, 2u);
  EXPECT_EQ(cache.stats().entries, 3u);  // two patch sets and their one topology

  // The content's hash is the whole key: a call without it would share one entry for all.
  EXPECT_THROW(cache.get(other, "", {}, nullptr), std::invalid_argument);
}

// An edit (the same topology, vertices moved) is new content. A topology is kept from its second
// patch set on (a one-off request keeps no refinement); later edits are preprocessed from their
// positions through it: the same pieces as from scratch, and no topology built again. Another
// topology builds its own.
TEST(PatchSetCache, AnEditReusesItsTopologyAndMakesThePatchSetFromScratch) {
  PatchSetCache cache(kBudget, kNoLimit);
  const ControlMesh first = cube();
  ControlMesh edit = cube(), again = cube();
  edit.positions[6] = {1.3f, 1.2f, -0.1f};
  again.positions[5] = {1.2f, -0.3f, 1.1f};
  ASSERT_NE(contentSha256(first), contentSha256(edit));
  cache.get(first, contentSha256(first), {}, nullptr);
  EXPECT_EQ(cache.stats().entries, 1u);  // no topology kept for a one-off
  cache.get(edit, contentSha256(edit), {}, nullptr);
  EXPECT_EQ(cache.topologyStats().misses, 2u);
  EXPECT_EQ(cache.topologyStats().hits, 0u);
  EXPECT_EQ(cache.stats().entries, 3u);  // two patch sets, one topology
  auto reused = cache.get(again, contentSha256(again), {}, nullptr);
  EXPECT_EQ(cache.stats().misses, 3u);
  EXPECT_EQ(cache.topologyStats().misses, 2u);
  EXPECT_EQ(cache.topologyStats().hits, 1u);
  const PatchSet scratch = buildPatchSet(again);
  ASSERT_EQ(reused->regular.bspline.size(), scratch.regular.bspline.size());
  EXPECT_EQ(std::memcmp(reused->regular.bspline.data(), scratch.regular.bspline.data(),
                        scratch.regular.bspline.size() * sizeof(ControlNet)),
            0);
  EXPECT_EQ(reused->rings.points, scratch.rings.points);

  ControlMesh creased = cube();
  creased.creases.push_back({0, 1, 2.0f});
  cache.get(creased, contentSha256(creased), {}, nullptr);
  EXPECT_EQ(cache.topologyStats().misses, 3u);
  EXPECT_EQ(cache.topologyStats().hits, 1u);
}

// A patch set is built for the finest tolerance asked so far (its EV chains' depth): a coarser
// request is served by a finer one's, a finer request builds its own (and keeps the topology).
TEST(PatchSetCache, AFinerRequestsPatchSetServesACoarserOne) {
  PatchSetCache cache(kBudget, kNoLimit);
  const ControlMesh mesh = cube();
  const std::string sha = contentSha256(mesh);
  auto coarse = cache.get(mesh, sha, {}, nullptr, 1e-2);
  EXPECT_EQ(cache.get(mesh, sha, {}, nullptr, 1e-2), coarse);
  EXPECT_EQ(cache.stats().misses, 1u);
  auto fine = cache.get(mesh, sha, {}, nullptr, 1e-6);
  EXPECT_NE(fine, coarse);
  EXPECT_EQ(cache.stats().misses, 2u);
  EXPECT_EQ(cache.get(mesh, sha, {}, nullptr, 1e-3), fine);  // 1e-6's chains serve 1e-3
  EXPECT_EQ(cache.get(mesh, sha, {}, nullptr, 1e-2), coarse);  // its own tier first
  // 1e-6 is deep enough for any request (kChainFloor): what a request of unknown ε gets.
  EXPECT_EQ(cache.get(mesh, sha, {}, nullptr, 0), fine);
  EXPECT_EQ(cache.stats().misses, 2u);
  // The finer build, the topology's second, kept it.
  EXPECT_EQ(cache.topologyStats().misses, 2u);
  EXPECT_EQ(cache.stats().entries, 3u);
}

TEST(PatchSetCache, ConcurrentColdGetsPreprocessOnceChargingTheBuilderOnly) {
  PatchSetCache cache(kBudget, kNoLimit);
  const ControlMesh mesh = cube();
  const std::string sha = contentSha256(mesh);
  constexpr int kWaiters = 3;
  Gate started, waiting[kWaiters], allWaiting;
  RecordedReservation builderMemory, waiterMemory[kWaiters];
  const CancellationToken builderCancel = builderToken(started, allWaiting, false);
  auto builder = std::async(std::launch::async,
                            [&] { return cache.get(mesh, sha, builderCancel, &builderMemory); });
  ASSERT_TRUE(started.wait());
  std::vector<std::future<std::shared_ptr<const PatchSet>>> waiters;
  for (int i = 0; i < kWaiters; ++i) {
    waiters.push_back(std::async(std::launch::async, [&, i, token = waiterToken(waiting[i])] {
      return cache.get(mesh, sha, token, &waiterMemory[i]);
    }));
  }
  for (Gate& gate : waiting) ASSERT_TRUE(gate.wait());
  allWaiting.open();

  const auto built = builder.get();
  ASSERT_TRUE(built);
  for (auto& waiter : waiters) EXPECT_EQ(waiter.get(), built);
  EXPECT_EQ(cache.stats().misses, 1u);
  EXPECT_EQ(cache.stats().hits, uint64_t(kWaiters));
  EXPECT_GT(builderMemory.reserved.load(), 0);
  for (const RecordedReservation& memory : waiterMemory) EXPECT_EQ(memory.reserved.load(), 0);
}

TEST(PatchSetCache, ACancelledBuilderLeavesThePreprocessingToAWaiter) {
  PatchSetCache cache(kBudget, kNoLimit);
  const ControlMesh mesh = cube();
  const std::string sha = contentSha256(mesh);
  Gate started, waiting;
  RecordedReservation builderMemory, waiterMemory;
  const CancellationToken builderCancel = builderToken(started, waiting, true);
  auto builder = std::async(std::launch::async,
                            [&] { return cache.get(mesh, sha, builderCancel, &builderMemory); });
  ASSERT_TRUE(started.wait());
  auto waiter = std::async(std::launch::async, [&, token = waiterToken(waiting)] {
    return cache.get(mesh, sha, token, &waiterMemory);
  });

  EXPECT_THROW(builder.get(), OperationCancelled);
  const auto built = waiter.get();
  ASSERT_TRUE(built);
  EXPECT_EQ(cache.stats().misses, 2u);  // the cancelled build and the waiter's
  EXPECT_GT(waiterMemory.reserved.load(), 0) << "the waiter built: its job holds the memory";
  EXPECT_EQ(cache.get(mesh, sha, {}, nullptr), built);
}

TEST(PatchSetCache, ACancelledWaiterStopsAtOnceWhileTheBuildGoesOn) {
  PatchSetCache cache(kBudget, kNoLimit);
  const ControlMesh mesh = cube();
  const std::string sha = contentSha256(mesh);
  Gate started, release, waiting;
  const CancellationToken builderCancel = builderToken(started, release, false);
  auto builder =
      std::async(std::launch::async, [&] { return cache.get(mesh, sha, builderCancel, nullptr); });
  ASSERT_TRUE(started.wait());
  std::atomic<bool> cancelled{false};
  auto waiter = std::async(std::launch::async, [&, token = waiterToken(waiting, &cancelled)] {
    return cache.get(mesh, sha, token, nullptr);
  });
  ASSERT_TRUE(waiting.wait());
  const auto cancelledAt = std::chrono::steady_clock::now();
  cancelled = true;
  ASSERT_EQ(waiter.wait_for(2s), std::future_status::ready) << "the waiter is still waiting";
  EXPECT_LT(std::chrono::steady_clock::now() - cancelledAt, 500ms);
  EXPECT_THROW(waiter.get(), OperationCancelled);

  EXPECT_EQ(builder.wait_for(100ms), std::future_status::timeout)
      << "the build stopped with the waiter";
  release.open();
  const auto built = builder.get();
  ASSERT_TRUE(built);
  EXPECT_EQ(cache.stats().misses, 1u);
  EXPECT_EQ(cache.get(mesh, sha, {}, nullptr), built);
}

TEST(PatchSetCache, TheMeshsOwnFailureReachesItsWaitersWithoutAnotherBuild) {
  PatchSetCache cache(kBudget, 10);  // a refinement limit no mesh with rings fits
  const ControlMesh mesh = cube();
  const std::string sha = contentSha256(mesh);
  Gate started, waiting;
  const CancellationToken builderCancel = builderToken(started, waiting, false);
  auto builder =
      std::async(std::launch::async, [&] { return cache.get(mesh, sha, builderCancel, nullptr); });
  ASSERT_TRUE(started.wait());
  auto waiter = std::async(std::launch::async, [&, token = waiterToken(waiting)] {
    return cache.get(mesh, sha, token, nullptr);
  });
  EXPECT_THROW(builder.get(), TesseraError);
  try {
    waiter.get();
    ADD_FAILURE() << "the waiter got a patch set";
  } catch (const TesseraError& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kLimitExceeded) << error.what();
  }
  EXPECT_EQ(cache.stats().misses, 1u);
  EXPECT_EQ(cache.stats().entries, 0u);
}

}  // namespace
}  // namespace tessera::server

namespace tessera::test {
namespace {

// bigguy's OBJ under `id`.
grpc::Status uploadBigguy(v1::MeshService::Stub& meshes, const std::string& id,
                          v1::Mesh* mesh = nullptr) {
  UploadResult result = uploadMessages(meshes, objUpload(id, readFile(modelPath("bigguy.obj"))));
  if (mesh) *mesh = result.mesh;
  return result.status;
}

v1::TessellateRequest tessellateRequest(const std::string& id) {
  v1::TessellateRequest request;
  request.set_name("meshes/" + id);
  request.set_relative(1e-2);
  return request;
}

// A GLB names the mesh it came from (asset.extras.source.name, and the glTF mesh and node):
// with that id written as another of the same length, the rest must be the same bytes.
std::string renamed(std::string glb, const std::string& from, const std::string& to) {
  const std::string was = "\"name\":\"" + from + "\"", is = "\"name\":\"" + to + "\"";
  for (size_t at = glb.find(was); at != std::string::npos; at = glb.find(was, at + is.size())) {
    glb.replace(at, was.size(), is);
  }
  return glb;
}

TEST(PatchSetCacheServer, OneContentUnderTwoIdsIsPreprocessedOnceIntoTheSameGlb) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {});
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  v1::Mesh first, second;
  ASSERT_TRUE(uploadBigguy(*meshes, "twin-a", &first).ok());
  const double decoded =
      seriesValue(httpGet(server->metricsAddress(), "/metrics"), "tessera_cache_bytes");
  ASSERT_TRUE(uploadBigguy(*meshes, "twin-b", &second).ok());
  EXPECT_EQ(first.sha256(), second.sha256());
  EXPECT_EQ(seriesValue(httpGet(server->metricsAddress(), "/metrics"), "tessera_cache_bytes"),
            decoded)
      << "the decoded mesh is held once";

  auto tessellation = v1::TessellationService::NewStub(server->channel());
  const Streamed a = tessellateOverGrpc(*tessellation, tessellateRequest("twin-a"));
  ASSERT_TRUE(a.status.ok()) << a.status.error_message();
  ASSERT_TRUE(a.problem.empty()) << a.problem;
  const Streamed b = tessellateOverGrpc(*tessellation, tessellateRequest("twin-b"));
  ASSERT_TRUE(b.status.ok()) << b.status.error_message();
  ASSERT_TRUE(b.problem.empty()) << b.problem;

  std::string metrics = httpGet(server->metricsAddress(), "/metrics");
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_misses_total"), 1) << metrics;
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_hits_total"), 1) << metrics;
  ASSERT_NE(b.glb.find("\"name\":\"twin-b\""), std::string::npos) << "the GLB names its mesh";
  EXPECT_TRUE(renamed(b.glb, "twin-b", "twin-a") == a.glb)
      << "the GLBs differ beyond the mesh's name";

  // Deleting one id leaves the other's content preprocessed.
  grpc::ClientContext context;
  prepare(context);
  v1::DeleteMeshRequest remove;
  remove.set_name("meshes/twin-a");
  google::protobuf::Empty empty;
  ASSERT_TRUE(meshes->DeleteMesh(&context, remove, &empty).ok());
  ASSERT_TRUE(tessellateOverGrpc(*tessellation, tessellateRequest("twin-b")).status.ok());
  metrics = httpGet(server->metricsAddress(), "/metrics");
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_misses_total"), 1) << metrics;
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_hits_total"), 2) << metrics;
}

TEST(PatchSetCacheServer, ConcurrentColdTessellationsOfOneMeshPreprocessItOnce) {
  constexpr int kCalls = 4;
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--max-concurrent-jobs", std::to_string(kCalls)});
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadBigguy(*meshes, "bigguy").ok());

  std::vector<std::future<Streamed>> calls;
  for (int i = 0; i < kCalls; ++i) {
    calls.push_back(std::async(std::launch::async, [&] {
      auto tessellation = v1::TessellationService::NewStub(server->channel());
      return tessellateOverGrpc(*tessellation, tessellateRequest("bigguy"));
    }));
  }
  std::vector<Streamed> results;
  for (auto& call : calls) results.push_back(call.get());
  for (const Streamed& result : results) {
    ASSERT_TRUE(result.status.ok()) << result.status.error_message();
    EXPECT_TRUE(result.glb == results[0].glb);
  }
  const std::string metrics = httpGet(server->metricsAddress(), "/metrics");
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_misses_total"), 1) << metrics;
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_hits_total"), kCalls - 1) << metrics;
}

}  // namespace
}  // namespace tessera::test
