#include "core/glb_writer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#define TINYGLTF_USE_CPP14
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>

#include "core/error.h"

namespace tessera {

namespace {

// glTF 2.0 §4.4 (binary glTF): a 12-byte header, then chunks of (length, type, data), each
// padded to 4 bytes (JSON with spaces, BIN with zeros).
constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963, kTriangles = 4;

size_t padded(size_t bytes) { return (bytes + 3) & ~size_t(3); }

// Indices as 16-bit integers when every vertex fits (a quarter less to send and to hash for
// typical results of up to ~130K triangles); 65535 is glTF's primitive-restart value and may not
// be used, so 16 bits hold at most 65535 vertices.
bool fitsShortIndices(const TriangleMesh& mesh) { return mesh.positions.size() <= 65535; }

// The accessor bounds glTF requires for positions: the exact float extremes.
void positionBounds(const std::vector<Vec3>& positions, nlohmann::json& lo, nlohmann::json& hi) {
  if (positions.empty()) return;
  Vec3 a = positions[0], b = positions[0];
  for (const Vec3& v : positions) {
    a = Vec3(std::min(a.x, v.x), std::min(a.y, v.y), std::min(a.z, v.z));
    b = Vec3(std::max(b.x, v.x), std::max(b.y, v.y), std::max(b.z, v.z));
  }
  lo = {double(a.x), double(a.y), double(a.z)};
  hi = {double(b.x), double(b.y), double(b.z)};
}

// The JSON chunk: one scene, one node, one mesh whose primitive reads positions, normals and
// indices from three views of the one binary buffer laid out in that order.
std::string glbJson(const TriangleMesh& mesh, const std::string& meshName, size_t indexBytes, size_t binBytes) {
  const size_t vertexBytes = mesh.positions.size() * sizeof(Vec3);
  nlohmann::json position = {{"bufferView", 0}, {"componentType", kFloat}, {"count", mesh.positions.size()}, {"type", "VEC3"}};
  if (!mesh.positions.empty()) positionBounds(mesh.positions, position["min"], position["max"]);
  const nlohmann::json json = {
      {"asset", {{"version", "2.0"}, {"generator", "Tessera"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"name", meshName}}}},
      {"meshes",
       {{{"name", meshName},
         {"primitives",
          {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}, {"mode", kTriangles}}}}}}},
      {"accessors",
       {position,
        {{"bufferView", 1}, {"componentType", kFloat}, {"count", mesh.normals.size()}, {"type", "VEC3"}},
        {{"bufferView", 2},
         {"componentType", fitsShortIndices(mesh) ? kUnsignedShort : kUnsignedInt},
         {"count", mesh.indices.size()},
         {"type", "SCALAR"}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", vertexBytes}, {"target", kArrayBuffer}},
        {{"buffer", 0}, {"byteOffset", vertexBytes}, {"byteLength", vertexBytes}, {"target", kArrayBuffer}},
        {{"buffer", 0}, {"byteOffset", 2 * vertexBytes}, {"byteLength", indexBytes}, {"target", kElementArrayBuffer}}}},
      {"buffers", {{{"byteLength", binBytes}}}}};
  return json.dump();
}

void put32(uint8_t* at, uint32_t value) { std::memcpy(at, &value, 4); }

// The binary chunk's data: positions, normals, then indices (16-bit where they fit), written in
// place on all cores.
void writeBin(const TriangleMesh& mesh, uint8_t* out) {
  const size_t vertexBytes = mesh.positions.size() * sizeof(Vec3);
  if (vertexBytes) std::memcpy(out, mesh.positions.data(), vertexBytes);
  if (vertexBytes) std::memcpy(out + vertexBytes, mesh.normals.data(), vertexBytes);
  uint8_t* indices = out + 2 * vertexBytes;
  if (!fitsShortIndices(mesh)) {
    if (!mesh.indices.empty()) std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    return;
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.indices.size(), 1 << 16), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const uint16_t index = static_cast<uint16_t>(mesh.indices[i]);
      std::memcpy(indices + i * sizeof(uint16_t), &index, sizeof index);
    }
  });
}

}  // namespace

// Written straight into the result (the JSON is small; the binary chunk is copied once).
std::vector<uint8_t> writeGlb(const TriangleMesh& mesh, const std::string& meshName) {
  if (mesh.normals.size() != mesh.positions.size()) throwInvalid("could not write the GLB: normals and positions differ in count");
  const size_t indexBytes = mesh.indices.size() * (fitsShortIndices(mesh) ? sizeof(uint16_t) : sizeof(uint32_t));
  const size_t binBytes = padded(2 * mesh.positions.size() * sizeof(Vec3) + indexBytes);
  std::string json = glbJson(mesh, meshName, indexBytes, binBytes);
  json.resize(padded(json.size()), ' ');
  const size_t total = 12 + 8 + json.size() + 8 + binBytes;
  if (total > UINT32_MAX) throwLimit("the GLB would be over 4 GiB, the format's limit; raise the tolerance");
  std::vector<uint8_t> glb(total, 0);
  put32(glb.data(), kGlbMagic);
  put32(glb.data() + 4, 2);
  put32(glb.data() + 8, uint32_t(total));
  put32(glb.data() + 12, uint32_t(json.size()));
  put32(glb.data() + 16, kChunkJson);
  std::memcpy(glb.data() + 20, json.data(), json.size());
  uint8_t* bin = glb.data() + 20 + json.size();
  put32(bin, uint32_t(binBytes));
  put32(bin + 4, kChunkBin);
  writeBin(mesh, bin + 8);
  return glb;
}

namespace {

// The bytes of accessor `index`, checked to lie inside its view and buffer.
struct AccessorBytes {
  const unsigned char* data;
  size_t count;
};

AccessorBytes accessorBytes(const tinygltf::Model& model, int index, int componentType, int type,
                            size_t elementSize, const char* what) {
  if (index < 0 || size_t(index) >= model.accessors.size()) throwInvalid(std::string("GLB has no ") + what);
  const auto& accessor = model.accessors[index];
  if (accessor.componentType != componentType || accessor.type != type) {
    throwInvalid(std::string("GLB ") + what + " accessor has an unexpected type");
  }
  if (accessor.bufferView < 0 || size_t(accessor.bufferView) >= model.bufferViews.size()) {
    throwInvalid(std::string("GLB ") + what + " accessor has no buffer view");
  }
  const auto& view = model.bufferViews[accessor.bufferView];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) {
    throwInvalid(std::string("GLB ") + what + " view has no buffer");
  }
  const auto& buffer = model.buffers[view.buffer];
  const size_t bytes = accessor.count * elementSize;
  if (view.byteStride != 0 && view.byteStride != elementSize) {
    throwInvalid(std::string("GLB ") + what + " view is interleaved");
  }
  if (accessor.byteOffset + bytes > view.byteLength || view.byteOffset + view.byteLength > buffer.data.size()) {
    throwInvalid(std::string("GLB ") + what + " accessor reaches past its buffer");
  }
  return {buffer.data.data() + view.byteOffset + accessor.byteOffset, accessor.count};
}

std::vector<Vec3> readVec3s(const tinygltf::Model& model, int index, const char* what) {
  AccessorBytes bytes = accessorBytes(model, index, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                      TINYGLTF_TYPE_VEC3, sizeof(Vec3), what);
  std::vector<Vec3> values(bytes.count);
  if (bytes.count) std::memcpy(values.data(), bytes.data, bytes.count * sizeof(Vec3));
  return values;
}

template <typename Index>
std::vector<uint32_t> widenIndices(const AccessorBytes& bytes) {
  std::vector<Index> narrow(bytes.count);
  if (bytes.count) std::memcpy(narrow.data(), bytes.data, bytes.count * sizeof(Index));
  return std::vector<uint32_t>(narrow.begin(), narrow.end());
}

std::vector<uint32_t> readIndices(const tinygltf::Model& model, int index) {
  if (index >= 0 && size_t(index) < model.accessors.size() &&
      model.accessors[index].componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
    return widenIndices<uint16_t>(accessorBytes(model, index, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                                TINYGLTF_TYPE_SCALAR, sizeof(uint16_t), "index"));
  }
  return widenIndices<uint32_t>(accessorBytes(model, index, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                              TINYGLTF_TYPE_SCALAR, sizeof(uint32_t), "index"));
}

int attribute(const tinygltf::Primitive& primitive, const std::string& name) {
  auto found = primitive.attributes.find(name);
  if (found == primitive.attributes.end()) throwInvalid("GLB primitive has no " + name);
  return found->second;
}

}  // namespace

TriangleMesh readGlb(const std::vector<uint8_t>& bytes) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  if (!loader.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(), unsigned(bytes.size()))) {
    throwInvalid("not a readable GLB: " + error);
  }
  if (model.meshes.size() != 1 || model.meshes[0].primitives.size() != 1) throwInvalid("expected one primitive");
  const auto& primitive = model.meshes[0].primitives[0];
  TriangleMesh mesh;
  mesh.positions = readVec3s(model, attribute(primitive, "POSITION"), "position");
  mesh.normals = readVec3s(model, attribute(primitive, "NORMAL"), "normal");
  mesh.indices = readIndices(model, primitive.indices);
  for (uint32_t index : mesh.indices) {
    if (index >= mesh.positions.size()) throwInvalid("GLB index " + std::to_string(index) + " has no vertex");
  }
  return mesh;
}

}  // namespace tessera
