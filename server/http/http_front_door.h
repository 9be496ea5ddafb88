// tessera-server's HTTP/1.1 front door (cpp-httplib), for clients that cannot speak gRPC: a
// browser, curl, a pipeline script. Off unless --http-listen is given; loopback by default. Every
// request becomes a call to the server's own gRPC services over an in-process channel, with the
// client's Authorization header, X-Request-Id and deadline (timeout_ms), so it meets exactly the
// same token, checks, limits, budgets, admission and messages as a gRPC client; the status maps to
// HTTP (http_status.h).
//
//   GET    /v1/meshes                               ListMeshes (page_size, page_token) → JSON
//   POST   /v1/meshes?id=ID[&display_name=NAME]     UploadMesh, the OBJ file as the body → 201 JSON
//   GET    /v1/meshes/ID                            GetMesh → JSON
//   DELETE /v1/meshes/ID                            DeleteMesh → 204
//   GET    /v1/meshes/ID/tessellation.glb?...       Tessellate (http_query.h) → model/gltf-binary,
//          streamed, with a strong ETag (the GLB is deterministic for the mesh's content, the
//          request and the server's version): If-None-Match answers 304 without tessellating
//   GET    /v1/meshes/ID/frame.png|frame.jpg?...    Render, one camera → image/png or image/jpeg
//   GET    /  and  /web/...                         the web viewer (client/web) and three.js, from
//                                                    the web root, when there is one
//
// JSON is protobuf's mapping of the API's messages (lowerCamelCase fields). With a CORS origin
// configured, responses carry Access-Control-Allow-Origin and preflights are answered.
#pragma once

#include <grpcpp/channel.h>

#include <memory>
#include <string>

#include "server/http/http_listener.h"

namespace tessera::server {

struct HttpFrontDoorOptions {
  std::string listen;      // HOST:PORT; port 0 picks a free one
  std::string corsOrigin;  // "" sends no CORS headers; "*" or one origin
  std::string version;     // the server's, part of every ETag
  std::string webRoot;     // the viewer's files (client/web, built); "" or missing: no viewer
};

class HttpFrontDoor {
 public:
  // Binds at once; throws std::runtime_error naming the address when it cannot.
  HttpFrontDoor(HttpFrontDoorOptions options, std::shared_ptr<grpc::Channel> services);
  ~HttpFrontDoor();
  HttpFrontDoor(const HttpFrontDoor&) = delete;
  HttpFrontDoor& operator=(const HttpFrontDoor&) = delete;

  // The stubs the routes call, over the in-process channel.
  struct Services;

  std::string address() const { return listener_.address(); }
  void start() { listener_.start(); }
  // Stops accepting and waits for the serving thread.
  void stop() { listener_.stop(); }

 private:
  HttpListener listener_;
  std::unique_ptr<Services> services_;
};

}  // namespace tessera::server
