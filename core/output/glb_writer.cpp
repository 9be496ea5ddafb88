#include "core/output/glb_writer.h"

#include <tbb/parallel_for.h>

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string_view>


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

// Whether any view is stored with EXT_meshopt_compression (a meshopt file whose every view is
// too large for the codecs' bound is written without the extension).
bool anyCompressed(const std::vector<View>& views) {
  return std::any_of(views.begin(), views.end(), [](const View& view) { return !view.compressed.empty(); });
}

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

// meshoptimizer's codecs run to their end once started, at ~170-200 MB of input a second on this
// 2-core VM when it is busy (bench/RUNAWAY-RESULTS.md): a view whose codec would read more than
// kMostCodecBytes is stored as it is, uncompressed (EXT_meshopt_compression is per view), so no
// codec call keeps a cancelled call running for more than ~0.4 s. Attributes of up to 5.6M
// vertices (float positions) and triangles of up to 5.6M triangles are compressed.
constexpr size_t kMostCodecBytes = size_t(64) << 20;

void compressAttributes(View& view) {
  if (view.size > kMostCodecBytes) return;
  view.compressed.resize(meshopt_encodeVertexBufferBound(view.count, view.stride));
  view.compressed.resize(meshopt_encodeVertexBuffer(view.compressed.data(), view.compressed.size(),
                                                    view.data, view.count, view.stride));
}

void compressTriangles(View& view, const std::vector<uint32_t>& indices, size_t vertices) {
  if (indices.size() * sizeof(uint32_t) > kMostCodecBytes) return;
  view.compressed.resize(meshopt_encodeIndexBufferBound(indices.size(), vertices));
  view.compressed.resize(
      meshopt_encodeIndexBuffer(view.compressed.data(), view.compressed.size(), indices.data(), indices.size()));
}

// meshoptimizer's vertex-cache ordering runs to its end once started, about 0.2 s a million
// triangles on one core (more on a busy one), past a cancelled call's deadline. Larger outputs are
// ordered in runs of kCacheOrderRun triangles, each over its own vertices (numbered in first use),
// with the checkpoint before each: a cancelled call waits for one run (bench/RUNAWAY-RESULTS.md).
// The runs are consecutive in the tessellator's order, tile by tile, so a run's border costs the
// cache a few misses. Outputs of up to kCacheOrderRun triangles are ordered in one piece, as they
// always were (the same bytes).
constexpr size_t kCacheOrderRun = size_t(1) << 19;

void orderForVertexCache(std::vector<uint32_t>& ordered, const std::vector<uint32_t>& indices, size_t vertexCount,
                         const std::function<void()>& checkpoint) {
  ordered.resize(indices.size());
  if (indices.size() <= 3 * kCacheOrderRun) {
    meshopt_optimizeVertexCache(ordered.data(), indices.data(), indices.size(), vertexCount);
    return;
  }
  std::vector<uint32_t> local(vertexCount, ~0u);  // a mesh vertex's number in the run; ~0u: not in it
  std::vector<uint32_t> global, runIndices, runOrdered;  // the run's vertices, its triangles, ordered
  for (size_t first = 0; first < indices.size(); first += 3 * kCacheOrderRun) {
    if (checkpoint) checkpoint();
    const size_t end = std::min(indices.size(), first + 3 * kCacheOrderRun);
    global.clear();
    runIndices.resize(end - first);
    for (size_t i = first; i < end; ++i) {
      uint32_t& number = local[indices[i]];
      if (number == ~0u) number = uint32_t(global.size()), global.push_back(indices[i]);
      runIndices[i - first] = number;
    }
    runOrdered.resize(runIndices.size());
    meshopt_optimizeVertexCache(runOrdered.data(), runIndices.data(), runIndices.size(), global.size());
    for (size_t i = first; i < end; ++i) ordered[i] = global[runOrdered[i - first]];
    for (const uint32_t v : global) local[v] = ~0u;
  }
}

// body(first, end) over [0, n) in slices of kSlice with the checkpoint between them: a pass over
// a large mesh's vertices or indices is no stretch without one (tens of milliseconds a slice).
constexpr size_t kSlice = size_t(1) << 20;

template <typename Body>
void inSlices(size_t n, const std::function<void()>& checkpoint, const Body& body) {
  for (size_t first = 0; first < n; first += kSlice) {
    if (first > 0 && checkpoint) checkpoint();
    body(first, std::min(n, first + kSlice));
  }
}

// Vertices numbered in first use by `indices`, which are renumbered so (what meshoptimizer's
// optimizeVertexFetchRemap and remapIndexBuffer compute, in slices); remap[v] is ~0u for an
// unused vertex. Returns the vertices used.
size_t renumberInFirstUse(std::vector<uint32_t>& indices, std::vector<uint32_t>& remap,
                          const std::function<void()>& checkpoint) {
  uint32_t next = 0;
  inSlices(indices.size(), checkpoint, [&](size_t first, size_t end) {
    for (size_t i = first; i < end; ++i) {
      uint32_t& number = remap[indices[i]];
      if (number == ~0u) number = next++;
      indices[i] = number;
    }
  });
  return next;
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
  const auto checkpoint = [&options] {
    if (options.checkpoint) options.checkpoint();
  };
  const size_t vertexCount = mesh.positions.size();
  const bool compress = options.encoding == GlbEncoding::kMeshopt;
  std::vector<uint32_t> reordered;  // meshopt: the triangles in cache order, vertices renumbered
  const std::vector<uint32_t>& indices = compress ? reordered : mesh.indices;
  std::vector<uint32_t> order(vertexCount);  // stored vertex k is mesh vertex order[k]
  std::iota(order.begin(), order.end(), 0u);
  size_t stored = vertexCount;
  if (compress && !mesh.indices.empty()) {
    orderForVertexCache(reordered, mesh.indices, vertexCount, options.checkpoint);
    checkpoint();
    std::vector<uint32_t> remap(vertexCount, ~0u);
    stored = renumberInFirstUse(reordered, remap, options.checkpoint);
    checkpoint();
    order.assign(stored, 0);
    inSlices(vertexCount, options.checkpoint, [&](size_t first, size_t end) {
      for (size_t v = first; v < end; ++v) {
        if (remap[v] != ~0u) order[remap[v]] = uint32_t(v);
      }
    });
  }
  Stored result;
  std::vector<QuantizedNormal> normals(stored);
  inSlices(stored, options.checkpoint, [&](size_t first, size_t end) {
    for (size_t k = first; k < end; ++k) normals[k] = quantizeNormal(mesh.normals[order[k]]);
  });
  result.normalType = kByte;
  checkpoint();
  if (options.positions) {
    std::vector<QuantizedPosition> positions(stored);
    std::array<int, 3> lo{32767, 32767, 32767}, hi{-32767, -32767, -32767};
    inSlices(stored, options.checkpoint, [&](size_t first, size_t end) {
      for (size_t k = first; k < end; ++k) {
        positions[k].q = options.positions->quantize(mesh.positions[order[k]]);
        for (int a = 0; a < 3; ++a) lo[a] = std::min<int>(lo[a], positions[k].q[a]), hi[a] = std::max<int>(hi[a], positions[k].q[a]);
      }
    });
    result.positionType = kShort;
    for (int a = 0; a < 3; ++a) result.positionMin[a] = lo[a], result.positionMax[a] = hi[a];
    checkpoint();
    result.views.push_back(ownedViewOf(positions));
  } else {
    std::vector<Vec3> positions(stored);
    inSlices(stored, options.checkpoint, [&](size_t first, size_t end) {
      for (size_t k = first; k < end; ++k) positions[k] = mesh.positions[order[k]];
    });
    checkpoint();
    positionBounds(positions, result);
    result.views.push_back(ownedViewOf(positions));
  }
  checkpoint();
  result.views.push_back(ownedViewOf(normals));
  View index = indexView(indices, stored);
  if (compress && index.owned.empty() && index.shortIndices.empty()) index = ownedViewOf(indices, kElementArrayBuffer);  // local
  result.views.push_back(std::move(index));
  if (!mesh.uvs.empty()) {
    std::vector<std::array<float, 2>> uvs(stored);
    inSlices(stored, options.checkpoint, [&](size_t first, size_t end) {
      for (size_t k = first; k < end; ++k) uvs[k] = {mesh.uvs[2 * order[k]], mesh.uvs[2 * order[k] + 1]};
    });
    checkpoint();
    result.views.push_back(ownedViewOf(uvs));
  }
  if (compress) {
    useSpecifiedCodecVersions();
    checkpoint();
    compressAttributes(result.views[0]);
    checkpoint();
    compressAttributes(result.views[1]);
    checkpoint();
    compressTriangles(result.views[2], indices, stored);
    checkpoint();
    if (result.views.size() > 3) compressAttributes(result.views[3]);
  }
  return result;
}

// The JSON chunk written directly, keys in the byte order nlohmann::json keeps them (the files
// are the same as when it was built as a json tree and dumped; that tree cost ~210K instructions
// a call, 10 % of a small request's whole time). Numbers and strings go through nlohmann's own
// serializer, so their formatting and escaping stay its.
class JsonChunk {
 public:
  JsonChunk& raw(std::string_view text) {
    text_ += text;
    return *this;
  }
  // `"key":`, after a comma unless it opens its object.
  JsonChunk& key(std::string_view name) {
    if (text_.back() != '{' && text_.back() != '[') text_ += ',';
    text_ += '"';
    text_ += name;
    return raw("\":");
  }
  // A value in an array (a comma before all but the first).
  JsonChunk& item() {
    if (text_.back() != '[') text_ += ',';
    return *this;
  }
  JsonChunk& number(size_t value) { return raw(std::to_string(value)); }
  JsonChunk& number(int value) { return raw(std::to_string(value)); }
  JsonChunk& number(double value) { return raw(nlohmann::json(value).dump()); }
  JsonChunk& string(const std::string& value) { return raw(nlohmann::json(value).dump()); }
  JsonChunk& vector(const double (&v)[3]) {
    raw("[").number(v[0]).raw(",").number(v[1]).raw(",").number(v[2]);
    return raw("]");
  }
  std::string take() { return std::move(text_); }

 private:
  std::string text_;
};

void writeExtras(const GlbOptions& options, JsonChunk& json) {
  const GlbDescription& d = options.description;
  json.raw("{").key("encoding").string(glbEncodingName(options.encoding));
  json.key("guaranteedBound").number(d.guaranteedBound);
  if (d.pixelAccuracy) json.key("pixelAccuracy").number(*d.pixelAccuracy);
  if (options.positions) json.key("positionError").number(options.positions->maxError);
  json.key("source").raw("{").key("name").string(d.sourceName);
  if (!d.sourceSha256.empty()) json.key("sha256").string(d.sourceSha256);
  json.raw("}");
  if (d.tolerance) json.key("tolerance").number(*d.tolerance);
  if (d.uniformLevel > 0) json.key("uniformLevel").number(d.uniformLevel);
  json.raw("}");
}

void writeAccessor(JsonChunk& json, size_t view, int componentType, size_t count) {
  json.item().raw("{").key("bufferView").number(view).key("componentType").number(componentType);
  json.key("count").number(count);
}

void writeAccessors(const Stored& stored, JsonChunk& json) {
  json.key("accessors").raw("[");
  writeAccessor(json, 0, stored.positionType, stored.views[0].count);
  if (stored.views[0].count > 0) {
    const auto& lo = stored.positionMin;
    const auto& hi = stored.positionMax;
    json.key("max").vector({hi[0], hi[1], hi[2]}).key("min").vector({lo[0], lo[1], lo[2]});
  }
  json.key("type").string("VEC3").raw("}");
  writeAccessor(json, 1, stored.normalType, stored.views[1].count);
  if (stored.normalType == kByte) json.key("normalized").raw("true");
  json.key("type").string("VEC3").raw("}");
  const View& indices = stored.views[2];
  writeAccessor(json, 2, indices.stride == 2 ? kUnsignedShort : kUnsignedInt, indices.count);
  json.key("type").string("SCALAR").raw("}");
  if (stored.views.size() > 3) {
    writeAccessor(json, 3, kFloat, stored.views[3].count);
    json.key("type").string("VEC2").raw("}");
  }
  json.raw("]");
}

void writeBufferViews(const Stored& stored, bool compressed, size_t binBytes, JsonChunk& json) {
  json.key("bufferViews").raw("[");
  size_t binOffset = 0, fallbackOffset = 0;
  for (const View& view : stored.views) {
    // A view too large for the codecs is stored as it is, in the BIN chunk, beside compressed ones.
    const bool packed = compressed && !view.compressed.empty();
    json.item().raw("{").key("buffer").number(size_t(packed ? 1 : 0)).key("byteLength").number(view.size);
    json.key("byteOffset").number(packed ? fallbackOffset : binOffset);
    // Vertex attributes name their stride (quantized ones are padded past their element).
    if (view.target == kArrayBuffer) json.key("byteStride").number(view.stride);
    if (packed) {
      fallbackOffset += padded(view.size);
      json.key("extensions").raw("{").key(kMeshopt).raw("{").key("buffer").number(size_t(0));
      json.key("byteLength").number(view.compressed.size()).key("byteOffset").number(binOffset);
      json.key("byteStride").number(view.stride).key("count").number(view.count);
      json.key("mode").string(view.target == kArrayBuffer ? "ATTRIBUTES" : "TRIANGLES").raw("}}");
      binOffset += padded(view.compressed.size());
    } else {
      binOffset += padded(view.size);
    }
    json.key("target").number(view.target).raw("}");
  }
  json.raw("]").key("buffers").raw("[{").key("byteLength").number(binBytes).raw("}");
  if (compressed) {
    json.raw(",{").key("byteLength").number(fallbackOffset);
    json.key("extensions").raw("{").key(kMeshopt).raw("{").key("fallback").raw("true}}}");
  }
  json.raw("]");
}

// The JSON chunk: one scene, one node (carrying the quantization grid's translation and scale),
// one mesh whose primitive reads positions, normals and indices from three views (and texture
// coordinates from a fourth).
std::string glbJson(const Stored& stored, const GlbOptions& options, size_t binBytes) {
  const std::string& name = options.description.sourceName;
  const bool compressed = options.encoding == GlbEncoding::kMeshopt && anyCompressed(stored.views);
  JsonChunk json;
  json.raw("{");
  writeAccessors(stored, json);
  json.key("asset").raw("{").key("extras");
  writeExtras(options, json);
  json.key("generator").string(std::string("Tessera ") + kVersion).key("version").string("2.0").raw("}");
  writeBufferViews(stored, compressed, binBytes, json);
  std::vector<const char*> extensions;
  if (options.encoding != GlbEncoding::kFloat) extensions.push_back(kQuantization);
  if (compressed) extensions.push_back(kMeshopt);
  for (const char* list : {"extensionsRequired", "extensionsUsed"}) {
    if (extensions.empty()) break;
    json.key(list).raw("[");
    for (const char* extension : extensions) json.item().string(extension);
    json.raw("]");
  }
  json.key("meshes").raw("[{").key("name").string(name).key("primitives").raw("[{");
  json.key("attributes").raw("{").key("NORMAL").number(1).key("POSITION").number(0);
  if (stored.views.size() > 3) json.key("TEXCOORD_0").number(3);
  json.raw("}");
  json.key("indices").number(2).key("mode").number(kTriangles).raw("}]}]");
  json.key("nodes").raw("[{").key("mesh").number(0).key("name").string(name);
  // The node carries the mesh's origin (far from the origin, the positions are relative to it)
  // and the quantization grid's centre, relative to that origin, in double precision.
  const Vec3d& origin = stored.origin;
  if (options.positions) {
    const PositionQuantization& q = *options.positions;
    json.key("scale").vector({q.step, q.step, q.step});
    json.key("translation").vector({origin.x + q.center.x, origin.y + q.center.y, origin.z + q.center.z});
  } else if (origin.x != 0 || origin.y != 0 || origin.z != 0) {
    json.key("translation").vector({origin.x, origin.y, origin.z});
  }
  json.raw("}]").key("scene").number(0).key("scenes").raw("[{").key("nodes").raw("[0]}]}");
  return json.take();
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
  if (options.checkpoint) options.checkpoint();
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
    // A view of a large float file is hundreds of megabytes to copy.
    if (options.checkpoint) options.checkpoint();
    const bool compressed = !view.compressed.empty();
    const size_t size = compressed ? view.compressed.size() : view.size;
    const uint8_t* data = compressed ? view.compressed.data() : view.data;
    if (size) glb.insert(glb.end(), data, data + size);
    glb.resize(glb.size() + padded(size) - size, 0);
  }
  return glb;
}

}  // namespace tessera
