#include "tests/support/glb_reader.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>

#include "core/base/error.h"

namespace tessera::testing {
namespace {

constexpr const char* kMeshopt = "EXT_meshopt_compression";

uint32_t get32(const uint8_t* at) {
  uint32_t value;
  std::memcpy(&value, at, 4);
  return value;
}

void put32(uint8_t* at, uint32_t value) {
  std::memcpy(at, &value, 4);
}

// The longest buffer the JSON chunk (glTF 2.0 §4.4: after the 12-byte header and its own 8) names.
size_t longestBuffer(const std::vector<uint8_t>& glb, size_t jsonLength) {
  const auto begin = glb.begin() + 20;
  const nlohmann::json json =
      nlohmann::json::parse(begin, begin + std::ptrdiff_t(jsonLength), nullptr, false);
  size_t longest = 0;
  if (!json.is_object() || !json.contains("buffers") || !json["buffers"].is_array()) return longest;
  for (const nlohmann::json& buffer : json["buffers"]) {
    if (buffer.is_object() && buffer.contains("byteLength") &&
        buffer["byteLength"].is_number_unsigned()) {
      longest = std::max(longest, buffer["byteLength"].get<size_t>());
    }
  }
  return longest;
}

// tinygltf (2.7.0, and upstream to date) fills every buffer without a uri from the BIN chunk and
// refuses one longer than the chunk, which EXT_meshopt_compression's fallback buffer (the
// uncompressed views' length, no data) always is. So it is handed the file with the BIN chunk
// zero-extended to the longest buffer: buffer 0 keeps its own bytes, the fallback's are never read.
std::vector<uint8_t> withRoomForEveryBuffer(std::vector<uint8_t> glb) {
  if (glb.size() < 20 || get32(glb.data() + 8) != glb.size()) return glb;  // tinygltf refuses it
  const size_t jsonLength = get32(glb.data() + 12), binAt = 20 + jsonLength;
  if (binAt + 8 > glb.size()) return glb;
  const size_t binLength = get32(glb.data() + binAt);
  const size_t wanted = (longestBuffer(glb, jsonLength) + 3) & ~size_t(3);
  if (wanted <= binLength || binAt + 8 + binLength > glb.size()) return glb;
  glb.insert(glb.begin() + std::ptrdiff_t(binAt + 8 + binLength), wanted - binLength, 0);
  put32(glb.data() + binAt, uint32_t(wanted));
  put32(glb.data() + 8, uint32_t(glb.size()));
  return glb;
}

tinygltf::Model load(const std::vector<uint8_t>& bytes) {
  const std::vector<uint8_t> glb = withRoomForEveryBuffer(bytes);
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  if (!loader.LoadBinaryFromMemory(&model, &error, &warning, glb.data(), unsigned(glb.size()))) {
    throwInvalid("not a readable GLB: " + error);
  }
  return model;
}

// `length` bytes at `offset` of the BIN chunk, buffer 0 (the only buffer a GLB of ours fills).
const uint8_t* binRange(const tinygltf::Model& model, int buffer, size_t offset, size_t length,
                        const std::string& what) {
  if (buffer != 0 || model.buffers.empty() || offset > model.buffers[0].data.size() ||
      length > model.buffers[0].data.size() - offset) {
    throwInvalid("GLB " + what + " view reaches past its buffer");
  }
  return model.buffers[0].data.data() + offset;
}

size_t member(const tinygltf::Value& object, const char* key) {
  const tinygltf::Value& value = object.Get(key);
  return value.IsNumber() && value.GetNumberAsDouble() >= 0 ? size_t(value.GetNumberAsDouble()) : 0;
}

std::vector<uint8_t> decodeMeshopt(const tinygltf::Model& model, const tinygltf::BufferView& view,
                                   const tinygltf::Value& extension, const std::string& what) {
  const size_t stride = member(extension, "byteStride"), count = member(extension, "count");
  const size_t length = member(extension, "byteLength");
  const uint8_t* data = binRange(model, int(member(extension, "buffer")),
                                 member(extension, "byteOffset"), length, what);
  const tinygltf::Value& modeValue = extension.Get("mode");
  const std::string mode = modeValue.IsString() ? modeValue.Get<std::string>() : "";
  if (stride == 0 || stride > 256 || count * stride != view.byteLength) {
    throwInvalid("GLB " + what + " view's compressed layout does not match it");
  }
  std::vector<uint8_t> bytes(view.byteLength);
  const int status =
      mode == "ATTRIBUTES"  ? meshopt_decodeVertexBuffer(bytes.data(), count, stride, data, length)
      : mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(bytes.data(), count, stride, data, length)
                            : -1;
  if (status != 0) throwInvalid("GLB " + what + " view does not decode (mode \"" + mode + "\")");
  return bytes;
}

// A view's bytes as a reader sees them: from the BIN chunk, or decoded from
// EXT_meshopt_compression.
std::vector<uint8_t> viewBytes(const tinygltf::Model& model, int index, const std::string& what) {
  if (index < 0 || size_t(index) >= model.bufferViews.size())
    throwInvalid("GLB has no " + what + " view");
  const tinygltf::BufferView& view = model.bufferViews[size_t(index)];
  const auto compressed = view.extensions.find(kMeshopt);
  if (compressed != view.extensions.end())
    return decodeMeshopt(model, view, compressed->second, what);
  const uint8_t* data = binRange(model, view.buffer, view.byteOffset, view.byteLength, what);
  return std::vector<uint8_t>(data, data + view.byteLength);
}

// Element k of an accessor of one of the types writeGlb stores: components as floats (normalized
// integers as glTF §3.11 maps them), or an index.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, int index, int type, const std::string& what) {
    if (index < 0 || size_t(index) >= model.accessors.size()) throwInvalid("GLB has no " + what);
    const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
    componentType_ = accessor.componentType;
    normalized_ = accessor.normalized;
    count_ = accessor.count;
    const int component = tinygltf::GetComponentSizeInBytes(uint32_t(componentType_));
    if (accessor.type != type || component <= 0)
      throwInvalid("GLB " + what + " accessor has an unexpected type");
    const size_t element = size_t(component * tinygltf::GetNumComponentsInType(uint32_t(type)));
    bytes_ = viewBytes(model, accessor.bufferView, what);
    const size_t viewStride = model.bufferViews[size_t(accessor.bufferView)].byteStride;
    stride_ = viewStride > 0 ? viewStride : element;
    offset_ = accessor.byteOffset;
    if (count_ > 0 &&
        (stride_ < element || offset_ + (count_ - 1) * stride_ + element > bytes_.size())) {
      throwInvalid("GLB " + what + " accessor reaches past its buffer");
    }
  }
  size_t count() const { return count_; }
  float component(size_t k, int c) const {
    const uint8_t* at =
        bytes_.data() + offset_ + k * stride_ +
        size_t(c) * size_t(tinygltf::GetComponentSizeInBytes(uint32_t(componentType_)));
    switch (componentType_) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return load<float>(at);
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        return scaled(load<int16_t>(at), 32767.0f);
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return scaled(load<int8_t>(at), 127.0f);
    }
    throwInvalid("GLB attribute has a component type writeGlb does not write");
  }
  uint32_t index(size_t k) const {
    const uint8_t* at = bytes_.data() + offset_ + k * stride_;
    if (componentType_ == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) return load<uint16_t>(at);
    if (componentType_ == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) return load<uint32_t>(at);
    throwInvalid("GLB indices are neither 16- nor 32-bit");
  }

 private:
  template <typename T>
  static T load(const uint8_t* at) {
    T value;
    std::memcpy(&value, at, sizeof value);
    return value;
  }
  float scaled(float value, float largest) const {
    return normalized_ ? std::max(value / largest, -1.0f) : value;
  }

  std::vector<uint8_t> bytes_;
  size_t offset_ = 0, stride_ = 0, count_ = 0;
  int componentType_ = 0;
  bool normalized_ = false;
};

// The node's translation or scale (its default when absent), as a viewer's float32 values.
std::array<float, 3> nodeVector(const std::vector<double>& vector, float fallback) {
  if (vector.size() != 3) return {fallback, fallback, fallback};
  return {float(vector[0]), float(vector[1]), float(vector[2])};
}

int attribute(const tinygltf::Primitive& primitive, const char* name) {
  const auto found = primitive.attributes.find(name);
  if (found == primitive.attributes.end())
    throwInvalid(std::string("GLB primitive has no ") + name);
  return found->second;
}

// Positions through the node's translation and scale, in float as a viewer computes them.
std::vector<Vec3> viewedPositions(const tinygltf::Model& model, const AccessorReader& positions) {
  const bool hasNode = !model.nodes.empty();
  const std::array<float, 3> translation =
      nodeVector(hasNode ? model.nodes[0].translation : std::vector<double>{}, 0);
  const std::array<float, 3> scale =
      nodeVector(hasNode ? model.nodes[0].scale : std::vector<double>{}, 1);
  std::vector<Vec3> viewed(positions.count());
  for (size_t k = 0; k < positions.count(); ++k) {
    float p[3];
    for (int a = 0; a < 3; ++a) p[a] = translation[a] + scale[a] * positions.component(k, a);
    viewed[k] = Vec3(p[0], p[1], p[2]);
  }
  return viewed;
}

std::vector<float> textureCoordinates(const tinygltf::Model& model,
                                      const tinygltf::Primitive& primitive, size_t vertices) {
  if (!primitive.attributes.count("TEXCOORD_0")) return {};
  const AccessorReader uvs(model, attribute(primitive, "TEXCOORD_0"), TINYGLTF_TYPE_VEC2,
                           "texture coordinate");
  if (uvs.count() != vertices) {
    throwInvalid("GLB has " + std::to_string(uvs.count()) + " texture coordinates for " +
                 std::to_string(vertices) + " vertices");
  }
  std::vector<float> values(2 * uvs.count());
  for (size_t k = 0; k < uvs.count(); ++k)
    values[2 * k] = uvs.component(k, 0), values[2 * k + 1] = uvs.component(k, 1);
  return values;
}

}  // namespace

TriangleMesh readGlb(const std::vector<uint8_t>& bytes) {
  const tinygltf::Model model = load(bytes);
  if (model.meshes.size() != 1 || model.meshes[0].primitives.size() != 1)
    throwInvalid("expected one primitive");
  const tinygltf::Primitive& primitive = model.meshes[0].primitives[0];
  const AccessorReader positions(model, attribute(primitive, "POSITION"), TINYGLTF_TYPE_VEC3,
                                 "position");
  const AccessorReader normals(model, attribute(primitive, "NORMAL"), TINYGLTF_TYPE_VEC3, "normal");
  const AccessorReader indices(model, primitive.indices, TINYGLTF_TYPE_SCALAR, "index");
  TriangleMesh mesh;
  mesh.positions = viewedPositions(model, positions);
  mesh.normals.resize(normals.count());
  for (size_t k = 0; k < normals.count(); ++k) {
    mesh.normals[k] =
        Vec3(normals.component(k, 0), normals.component(k, 1), normals.component(k, 2));
  }
  mesh.uvs = textureCoordinates(model, primitive, positions.count());
  mesh.indices.resize(indices.count());
  for (size_t k = 0; k < indices.count(); ++k) {
    mesh.indices[k] = indices.index(k);
    if (mesh.indices[k] >= mesh.positions.size())
      throwInvalid("GLB index " + std::to_string(mesh.indices[k]) + " has no vertex");
  }
  return mesh;
}

}  // namespace tessera::testing
