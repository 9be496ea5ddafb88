#include "core/output/glb_writer.h"

#include <tbb/parallel_for.h>

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>

#include "core/base/error.h"
#include "core/base/version.h"

namespace tessera {

namespace {

// glTF 2.0 §4.4 (binary glTF): a 12-byte header, then chunks of (length, type, data), each
// padded to 4 bytes (JSON with spaces, BIN with zeros).
constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr int kByte = 5120, kShort = 5122, kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963, kTriangles = 4;
constexpr const char* kMeshopt = "EXT_meshopt_compression";
constexpr const char* kQuantization = "KHR_mesh_quantization";

size_t padded(size_t bytes) { return (bytes + 3) & ~size_t(3); }

// Indices as 16-bit integers when every vertex fits (a quarter less to send and to hash for
// typical results of up to ~130K triangles); 65535 is glTF's primitive-restart value and may not
// be used, so 16 bits hold at most 65535 vertices.
bool fitsShortIndices(size_t vertices) { return vertices <= 65535; }

// Quantized attributes, padded so every element starts on 4 bytes (glTF §3.6.2.4).
struct QuantizedPosition {
  std::array<int16_t, 3> q;
  int16_t pad = 0;
};
struct QuantizedNormal {
  int8_t x, y, z, pad = 0;
};

QuantizedNormal quantizeNormal(const Vec3& n) {
  auto axis = [](float value) { return int8_t(std::clamp(std::nearbyint(value * 127.0f), -127.0f, 127.0f)); };
  return {axis(n.x), axis(n.y), axis(n.z)};
}

// One bufferView: its element layout and bytes (the mesh's own arrays where they are stored as
// they are), kept as they are or, with EXT_meshopt_compression, encoded (attributes or triangles
// mode) in the BIN chunk while the view itself lies in a placeholder buffer.
struct View {
  const uint8_t* data = nullptr;  // the bytes a reader sees
  size_t size = 0;
  std::vector<uint8_t> owned;     // those bytes when the mesh does not hold them
  std::vector<uint16_t> shortIndices;  // or, for 16-bit indices, these
  size_t stride = 0, count = 0;
  int target = kArrayBuffer;
  std::vector<uint8_t> compressed;  // empty: stored as is
};

template <typename T>
View viewOf(const std::vector<T>& values, int target = kArrayBuffer) {
  View view;
  view.stride = sizeof(T), view.count = values.size(), view.target = target;
  view.data = reinterpret_cast<const uint8_t*>(values.data());
  view.size = values.size() * sizeof(T);
  return view;
}

template <typename T>
View ownedViewOf(const std::vector<T>& values, int target = kArrayBuffer) {
  View view = viewOf(values, target);
  view.owned.assign(view.data, view.data + view.size);
  view.data = view.owned.data();
  return view;
}

// Texture coordinates, (u, v) floats per vertex: glTF's TEXCOORD_0 (float in every encoding,
// which KHR_mesh_quantization allows).
View uvView(const std::vector<float>& uvs) {
  View view = viewOf(uvs);
  view.stride = 2 * sizeof(float), view.count = uvs.size() / 2;
  return view;
}

View indexView(const std::vector<uint32_t>& indices, size_t vertices) {
  if (!fitsShortIndices(vertices)) return viewOf(indices, kElementArrayBuffer);
  View view;
  view.shortIndices.resize(indices.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, indices.size(), 1 << 16), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) view.shortIndices[i] = static_cast<uint16_t>(indices[i]);
  });
  view.stride = sizeof(uint16_t), view.count = indices.size(), view.target = kElementArrayBuffer;
  view.data = reinterpret_cast<const uint8_t*>(view.shortIndices.data());
  view.size = view.shortIndices.size() * sizeof(uint16_t);
  return view;
}

// The bitstream versions EXT_meshopt_compression specifies (attributes 0xa0, triangles 0xe1).
void useSpecifiedCodecVersions() {
  static std::once_flag once;
  std::call_once(once, [] {
    meshopt_encodeVertexVersion(0);
    meshopt_encodeIndexVersion(1);
  });
}

void compressAttributes(View& view) {
  view.compressed.resize(meshopt_encodeVertexBufferBound(view.count, view.stride));
  view.compressed.resize(meshopt_encodeVertexBuffer(view.compressed.data(), view.compressed.size(),
                                                    view.data, view.count, view.stride));
}

void compressTriangles(View& view, const std::vector<uint32_t>& indices, size_t vertices) {
  view.compressed.resize(meshopt_encodeIndexBufferBound(indices.size(), vertices));
  view.compressed.resize(
      meshopt_encodeIndexBuffer(view.compressed.data(), view.compressed.size(), indices.data(), indices.size()));
}

// The mesh as the file stores it: attributes in the encoding's types; for EXT_meshopt_compression
// triangles ordered for the vertex cache and vertices in first-use order, which is what its codecs
// compress well (the same triangles over the same vertices).
struct Stored {
  std::vector<View> views;  // positions, normals, indices, and texture coordinates when the mesh has them
  int positionType = kFloat, normalType = kFloat;
  std::array<double, 3> positionMin{}, positionMax{};
  Vec3d origin{0, 0, 0};  // the node's translation before quantization's (TriangleMesh::origin)
};

void positionBounds(const std::vector<Vec3>& positions, Stored& stored) {
  if (positions.empty()) return;
  Vec3 a = positions[0], b = positions[0];
  for (const Vec3& v : positions) {
    a = Vec3(std::min(a.x, v.x), std::min(a.y, v.y), std::min(a.z, v.z));
    b = Vec3(std::max(b.x, v.x), std::max(b.y, v.y), std::max(b.z, v.z));
  }
  stored.positionMin = {a.x, a.y, a.z};
  stored.positionMax = {b.x, b.y, b.z};
}

Stored storePlain(const TriangleMesh& mesh) {
  Stored stored;
  positionBounds(mesh.positions, stored);
  stored.views.push_back(viewOf(mesh.positions));
  stored.views.push_back(viewOf(mesh.normals));
  stored.views.push_back(indexView(mesh.indices, mesh.positions.size()));
  if (!mesh.uvs.empty()) stored.views.push_back(uvView(mesh.uvs));
  return stored;
}

Stored storeQuantized(const TriangleMesh& mesh, const GlbOptions& options) {
  const size_t vertexCount = mesh.positions.size();
  const bool compress = options.encoding == GlbEncoding::kMeshopt;
  std::vector<uint32_t> reordered;  // meshopt: the triangles in cache order, vertices renumbered
  const std::vector<uint32_t>& indices = compress ? reordered : mesh.indices;
  std::vector<uint32_t> order(vertexCount);  // stored vertex k is mesh vertex order[k]
  std::iota(order.begin(), order.end(), 0u);
  size_t stored = vertexCount;
  if (compress && !mesh.indices.empty()) {
    reordered.resize(mesh.indices.size());
    meshopt_optimizeVertexCache(reordered.data(), mesh.indices.data(), reordered.size(), vertexCount);
    std::vector<uint32_t> remap(vertexCount);
    stored = meshopt_optimizeVertexFetchRemap(remap.data(), reordered.data(), reordered.size(), vertexCount);
    meshopt_remapIndexBuffer(reordered.data(), reordered.data(), reordered.size(), remap.data());
    order.assign(stored, 0);
    for (uint32_t v = 0; v < vertexCount; ++v) {
      if (remap[v] != ~0u) order[remap[v]] = v;
    }
  }
  Stored result;
  std::vector<QuantizedNormal> normals(stored);
  for (size_t k = 0; k < stored; ++k) normals[k] = quantizeNormal(mesh.normals[order[k]]);
  result.normalType = kByte;
  if (options.positions) {
    std::vector<QuantizedPosition> positions(stored);
    std::array<int, 3> lo{32767, 32767, 32767}, hi{-32767, -32767, -32767};
    for (size_t k = 0; k < stored; ++k) {
      positions[k].q = options.positions->quantize(mesh.positions[order[k]]);
      for (int a = 0; a < 3; ++a) lo[a] = std::min<int>(lo[a], positions[k].q[a]), hi[a] = std::max<int>(hi[a], positions[k].q[a]);
    }
    result.positionType = kShort;
    for (int a = 0; a < 3; ++a) result.positionMin[a] = lo[a], result.positionMax[a] = hi[a];
    result.views.push_back(ownedViewOf(positions));
  } else {
    std::vector<Vec3> positions(stored);
    for (size_t k = 0; k < stored; ++k) positions[k] = mesh.positions[order[k]];
    positionBounds(positions, result);
    result.views.push_back(ownedViewOf(positions));
  }
  result.views.push_back(ownedViewOf(normals));
  View index = indexView(indices, stored);
  if (compress && index.owned.empty() && index.shortIndices.empty()) index = ownedViewOf(indices, kElementArrayBuffer);  // local
  result.views.push_back(std::move(index));
  if (!mesh.uvs.empty()) {
    std::vector<std::array<float, 2>> uvs(stored);
    for (size_t k = 0; k < stored; ++k) uvs[k] = {mesh.uvs[2 * order[k]], mesh.uvs[2 * order[k] + 1]};
    result.views.push_back(ownedViewOf(uvs));
  }
  if (compress) {
    useSpecifiedCodecVersions();
    compressAttributes(result.views[0]);
    compressAttributes(result.views[1]);
    compressTriangles(result.views[2], indices, stored);
    if (result.views.size() > 3) compressAttributes(result.views[3]);
  }
  return result;
}

// The glTF document, built as a tinygltf::Model and serialized by tinygltf. Debian's tinygltf
// (2.7.0) writes neither a buffer's extensions nor a view's, and takes a buffer's byteLength from
// the data it holds (the BIN chunk copied once more); so the buffers, and under meshopt the views'
// EXT_meshopt_compression objects, are added to the text it writes.
tinygltf::Value glbExtras(const GlbOptions& options) {
  const GlbDescription& d = options.description;
  tinygltf::Value::Object source{{"name", tinygltf::Value(d.sourceName)}};
  if (!d.sourceSha256.empty()) source["sha256"] = tinygltf::Value(d.sourceSha256);
  tinygltf::Value::Object extras{
      {"encoding", tinygltf::Value(std::string(glbEncodingName(options.encoding)))},
      {"guaranteedBound", tinygltf::Value(d.guaranteedBound)},
      {"source", tinygltf::Value(std::move(source))}};
  if (d.pixelAccuracy) extras["pixelAccuracy"] = tinygltf::Value(*d.pixelAccuracy);
  if (options.positions) extras["positionError"] = tinygltf::Value(options.positions->maxError);
  if (d.tolerance) extras["tolerance"] = tinygltf::Value(*d.tolerance);
  if (d.uniformLevel > 0) extras["uniformLevel"] = tinygltf::Value(d.uniformLevel);
  return tinygltf::Value(std::move(extras));
}

tinygltf::Accessor accessor(int view, int componentType, size_t count, int type) {
  tinygltf::Accessor a;
  a.bufferView = view, a.componentType = componentType, a.count = count, a.type = type;
  return a;
}

void addAccessors(const Stored& stored, tinygltf::Model& model) {
  tinygltf::Accessor positions = accessor(0, stored.positionType, stored.views[0].count, TINYGLTF_TYPE_VEC3);
  if (stored.views[0].count > 0) {
    positions.minValues.assign(stored.positionMin.begin(), stored.positionMin.end());
    positions.maxValues.assign(stored.positionMax.begin(), stored.positionMax.end());
  }
  model.accessors.push_back(std::move(positions));
  model.accessors.push_back(accessor(1, stored.normalType, stored.views[1].count, TINYGLTF_TYPE_VEC3));
  model.accessors.back().normalized = stored.normalType == kByte;
  const View& indices = stored.views[2];
  const int indexType = indices.stride == 2 ? kUnsignedShort : kUnsignedInt;
  model.accessors.push_back(accessor(2, indexType, indices.count, TINYGLTF_TYPE_SCALAR));
  if (stored.views.size() > 3) model.accessors.push_back(accessor(3, kFloat, stored.views[3].count, TINYGLTF_TYPE_VEC2));
}

// The views as a reader sees them: in buffer 0, or under meshopt in the placeholder buffer 1.
void addBufferViews(const Stored& stored, bool compressed, tinygltf::Model& model) {
  size_t offset = 0;
  for (const View& view : stored.views) {
    tinygltf::BufferView bufferView;
    bufferView.buffer = compressed ? 1 : 0;
    bufferView.byteLength = view.size, bufferView.byteOffset = offset, bufferView.target = view.target;
    // Vertex attributes name their stride (quantized ones are padded past their element).
    if (view.target == kArrayBuffer) bufferView.byteStride = view.stride;
    model.bufferViews.push_back(std::move(bufferView));
    offset += padded(view.size);
  }
}

// One mesh whose primitive reads positions, normals and indices from three views (and texture
// coordinates from a fourth), under one node in one scene.
void addMeshAndNode(const Stored& stored, const GlbOptions& options, tinygltf::Model& model) {
  const std::string& name = options.description.sourceName;
  tinygltf::Primitive primitive;
  primitive.attributes = {{"POSITION", 0}, {"NORMAL", 1}};
  if (stored.views.size() > 3) primitive.attributes["TEXCOORD_0"] = 3;
  primitive.indices = 2, primitive.mode = kTriangles;
  model.meshes.emplace_back().name = name;
  model.meshes.back().primitives.push_back(std::move(primitive));
  tinygltf::Node& node = model.nodes.emplace_back();
  node.mesh = 0, node.name = name;
  // The node carries the mesh's origin (far from the origin, the positions are relative to it)
  // and the quantization grid's centre, relative to that origin, in double precision.
  const Vec3d& origin = stored.origin;
  if (options.positions) {
    const PositionQuantization& q = *options.positions;
    node.scale = {q.step, q.step, q.step};
    node.translation = {origin.x + q.center.x, origin.y + q.center.y, origin.z + q.center.z};
  } else if (origin.x != 0 || origin.y != 0 || origin.z != 0) {
    node.translation = {origin.x, origin.y, origin.z};
  }
  model.scenes.emplace_back().nodes = {0};
  model.defaultScene = 0;
}

tinygltf::Model glbModel(const Stored& stored, const GlbOptions& options) {
  tinygltf::Model model;
  addAccessors(stored, model);
  model.asset.generator = std::string("Tessera ") + kVersion;
  model.asset.extras = glbExtras(options);
  addBufferViews(stored, options.encoding == GlbEncoding::kMeshopt, model);
  if (options.encoding != GlbEncoding::kFloat) model.extensionsUsed.push_back(kQuantization);
  if (options.encoding == GlbEncoding::kMeshopt) model.extensionsUsed.push_back(kMeshopt);
  model.extensionsRequired = model.extensionsUsed;
  addMeshAndNode(stored, options, model);
  return model;
}

// Under meshopt: each view's compressed bytes in buffer 0 (EXT_meshopt_compression), and the
// placeholder buffer 1 that the views themselves lie in.
std::string withMeshoptMembers(const std::string& text, const Stored& stored, size_t binBytes) {
  nlohmann::json document = nlohmann::json::parse(text);
  size_t binOffset = 0, fallbackBytes = 0;
  for (size_t k = 0; k < stored.views.size(); ++k) {
    const View& view = stored.views[k];
    document["bufferViews"][k]["extensions"][kMeshopt] = {
        {"buffer", 0}, {"byteLength", view.compressed.size()}, {"byteOffset", binOffset},
        {"byteStride", view.stride}, {"count", view.count},
        {"mode", view.target == kArrayBuffer ? "ATTRIBUTES" : "TRIANGLES"}};
    binOffset += padded(view.compressed.size());
    fallbackBytes += padded(view.size);
  }
  document["buffers"] = {{{"byteLength", binBytes}},
                         {{"byteLength", fallbackBytes}, {"extensions", {{kMeshopt, {{"fallback", true}}}}}}};
  return document.dump();
}

std::string glbJson(const Stored& stored, const GlbOptions& options, size_t binBytes) {
  const tinygltf::Model model = glbModel(stored, options);
  std::ostringstream stream;
  tinygltf::TinyGLTF().WriteGltfSceneToStream(&model, stream, false, false);
  std::string text = std::move(stream).str();
  if (options.encoding == GlbEncoding::kMeshopt) return withMeshoptMembers(text, stored, binBytes);
  // Its text ends in "}\n": buffer 0, the BIN chunk, becomes its last member.
  text.resize(text.rfind('}'));
  return text + ",\"buffers\":[{\"byteLength\":" + std::to_string(binBytes) + "}]}";
}

void put32(uint8_t* at, uint32_t value) { std::memcpy(at, &value, 4); }

}  // namespace

const char* glbEncodingName(GlbEncoding encoding) {
  switch (encoding) {
    case GlbEncoding::kQuantized: return "quantized";
    case GlbEncoding::kMeshopt: return "meshopt";
    case GlbEncoding::kFloat: break;
  }
  return "float";
}

GlbEncoding parseGlbEncoding(const std::string& name) {
  for (GlbEncoding e : {GlbEncoding::kFloat, GlbEncoding::kQuantized, GlbEncoding::kMeshopt}) {
    if (name == glbEncodingName(e)) return e;
  }
  throwInvalid("unknown GLB encoding \"" + name + "\" (float, quantized or meshopt)");
}

std::vector<uint8_t> writeGlb(const TriangleMesh& mesh, const GlbOptions& options) {
  if (mesh.normals.size() != mesh.positions.size()) throwInvalid("could not write the GLB: normals and positions differ in count");
  if (!mesh.uvs.empty() && mesh.uvs.size() != 2 * mesh.positions.size()) throwInvalid("could not write the GLB: UVs and positions differ in count");
  Stored stored = options.encoding == GlbEncoding::kFloat ? storePlain(mesh) : storeQuantized(mesh, options);
  stored.origin = mesh.origin;
  size_t binBytes = 0;
  for (const View& view : stored.views) binBytes += padded(view.compressed.empty() ? view.size : view.compressed.size());
  std::string json = glbJson(stored, options, binBytes);
  json.resize(padded(json.size()), ' ');
  const size_t total = 12 + 8 + json.size() + 8 + binBytes;
  if (total > UINT32_MAX) throwLimit("the GLB would be over 4 GiB, the format's limit; raise the tolerance");
  // Appended piece by piece into its room (not zero-filled first, then copied over).
  std::vector<uint8_t> glb;
  glb.reserve(total);
  auto append32 = [&glb](uint32_t value) {
    uint8_t bytes[4];
    put32(bytes, value);
    glb.insert(glb.end(), bytes, bytes + 4);
  };
  append32(kGlbMagic), append32(2), append32(uint32_t(total));
  append32(uint32_t(json.size())), append32(kChunkJson);
  glb.insert(glb.end(), json.begin(), json.end());
  append32(uint32_t(binBytes)), append32(kChunkBin);
  for (const View& view : stored.views) {
    const bool compressed = !view.compressed.empty();
    const size_t size = compressed ? view.compressed.size() : view.size;
    const uint8_t* data = compressed ? view.compressed.data() : view.data;
    if (size) glb.insert(glb.end(), data, data + size);
    glb.resize(glb.size() + padded(size) - size, 0);
  }
  return glb;
}

}  // namespace tessera
