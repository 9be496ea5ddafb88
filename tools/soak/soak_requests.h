// The requests of tools/soak (issue 16): normal ones, which a well-behaved client retries after
// the server's pushback until they succeed, hostile ones, each made to take memory or hold
// the server (the reproducers of the memory budget's issue, malformed input, abandoned and
// overdue calls), whose every answer must be one of the codes the API documents for them, and
// the cold storm's (issue 46): uploads of meshes the server has never seen, each tessellated once.
#pragma once

#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "client/remote_cold_copies.h"
#include "tessera/v1/mesh.grpc.pb.h"
#include "tessera/v1/render.grpc.pb.h"
#include "tessera/v1/tessellation.grpc.pb.h"

namespace tessera::soak {

// What the soak needs to know before the clients start.
struct SoakSetup {
  std::string token;
  std::string smallMesh;    // meshes/NAME of a character-sized mesh (normal requests)
  std::string largeMesh;    // meshes/NAME of a large mesh (hostile output requests)
  std::string smallObj;     // the small mesh's OBJ text (the creased upload is made from it)
  v1::Camera smallView;     // the small mesh whole in a 256 x 256 view
  bool renderAvailable = false;
  std::vector<cli::ColdSource> coldSources;  // the models the cold storm copies
  double coldTolerance = 1e-3;               // relative, of the cold storm's tessellations
  int seed = 1;                              // numbers the cold copies with the client and serial
};

// The bearer token (if any) and a deadline `seconds` from now on a call's context.
void prepare(grpc::ClientContext& context, const std::string& token, double seconds);

// One client's stubs on a channel of its own, as separate clients would have.
struct SoakClient {
  explicit SoakClient(const std::shared_ptr<grpc::Channel>& channel);
  std::unique_ptr<v1::MeshService::Stub> meshes;
  std::unique_ptr<v1::TessellationService::Stub> tessellation;
  std::unique_ptr<v1::RenderService::Stub> render;
  std::mt19937 random;
};

// One finished request: its kind, its final status, how many times the server pushed it back
// (normal requests only) and its wall time from the first attempt to the final answer.
enum class Role { kNormal, kHostile, kCold };

struct Outcome {
  std::string kind;
  Role role = Role::kNormal;
  grpc::StatusCode code = grpc::StatusCode::OK;
  std::string message;
  int pushbacks = 0;
  double ms = 0;
  bool pushedBack = false;  // RESOURCE_EXHAUSTED with the server's retry hint (busy)
  bool expected = true;    // the code is one the request may end with
  std::string sha256;      // a cold upload's content as the server stored it
};

// A normal request chosen at random (tessellations of the small mesh at two tolerances, a
// mesh lookup, a small frame), retried after each RESOURCE_EXHAUSTED pushback while its
// deadline allows.
Outcome normalRequest(SoakClient& client, const SoakSetup& setup);
// Both meshes tessellated once at 1e-2, so that their patch sets are built and cached; throws
// if either fails.
void warmUp(SoakClient& client, const SoakSetup& setup);
// The runaway's kind in reports: a legitimately long Tessellate with a 1 s deadline.
inline constexpr const char* kRunaway = "runaway 1e-5 (1 s deadline)";

// The runaway (bigguy at 1e-5, ~1.5 s alone) with a 0.3 s deadline, sent alone after the soak:
// the server must stop it at once. (Under a 3 GiB budget nothing much longer is admitted: bigguy at
// 1e-6, 17 M triangles, needs ~11 GiB for its output and is refused once planned.)
inline constexpr const char* kLastRunaway = "last runaway 1e-5 (0.3 s deadline)";
Outcome lastRunaway(SoakClient& client, const SoakSetup& setup);

// A hostile request chosen at random, or the runaway.
Outcome hostileRequest(SoakClient& client, const SoakSetup& setup, int clientIndex, uint64_t serial, bool runaway);

// A cold storm request: a copy of one of the cold sources, with content of its own, uploaded,
// tessellated once and deleted (its patch set stays in the server's cache until evicted); two
// outcomes, the upload's and the tessellation's, or one if the upload was refused. Each is
// retried after a pushback; OK, or RESOURCE_EXHAUSTED with a message, is what it may end with.
std::vector<Outcome> coldRequest(SoakClient& client, const SoakSetup& setup, int clientIndex, uint64_t serial);

// Every edge of the OBJ's faces a semi-sharp crease of sharpness 9.5 ("t crease" lines added).
std::string creasedEverywhere(const std::string& objText);

// Uploads OBJ text as meshes/id on a fresh context (whose trailers the caller may read); the
// call's status.
grpc::Status uploadObj(v1::MeshService::Stub& stub, grpc::ClientContext& context, const std::string& token,
                       const std::string& id, const std::string& text, int deadlineSeconds);

}  // namespace tessera::soak
