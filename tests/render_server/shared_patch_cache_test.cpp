// One patch-set cache for the whole server: a mesh rendered and then tessellated is preprocessed
// once, as the Prometheus counters of the cache show.
#include <gtest/gtest.h>

#include <string>

#include "tessera/v1/tessellation.grpc.pb.h"
#include "tests/render_server/render_test_support.h"

namespace tessera::test {
namespace {

class SharedPatchCacheTest : public RenderServerTest {};

grpc::Status tessellateBigguy(ServerProcess& server) {
  auto stub = v1::TessellationService::NewStub(server.channel());
  grpc::ClientContext context;
  prepare(context);
  v1::TessellateRequest request;
  request.set_name("meshes/bigguy");
  request.set_relative(1e-2);
  auto reader = stub->Tessellate(&context, request);
  v1::TessellateResponse message;
  while (reader->Read(&message)) {
  }
  return reader->Finish();
}

TEST_F(SharedPatchCacheTest, RenderAndTessellationPreprocessAMeshOnce) {
  RenderCall call = render(*renderStub(), renderRequest({framedCamera({0, 0, 1}, 32, 32)}));
  ASSERT_TRUE(call.status.ok()) << call.status.error_message();
  grpc::Status status = tessellateBigguy(server());
  ASSERT_TRUE(status.ok()) << status.error_message();

  std::string metrics = httpGet(server().metricsAddress(), "/metrics");
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_misses_total"), 1) << metrics;
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_hits_total"), 1) << metrics;
  EXPECT_GT(seriesValue(metrics, "tessera_patch_cache_bytes"), 0) << metrics;
}

}  // namespace
}  // namespace tessera::test
