#include "core/glb_writer.h"

#include <cstring>
#include <sstream>

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

template <typename T>
void appendBytes(std::vector<unsigned char>& buffer, const std::vector<T>& values) {
  size_t offset = buffer.size();
  buffer.resize(offset + values.size() * sizeof(T));
  if (!values.empty()) std::memcpy(buffer.data() + offset, values.data(), values.size() * sizeof(T));
}

int addView(tinygltf::Model& model, size_t offset, size_t length, int target) {
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = offset;
  view.byteLength = length;
  view.target = target;
  model.bufferViews.push_back(view);
  return int(model.bufferViews.size() - 1);
}

int addVec3Accessor(tinygltf::Model& model, int view, const std::vector<Vec3>& values, bool bounds) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  accessor.type = TINYGLTF_TYPE_VEC3;
  accessor.count = values.size();
  if (bounds && !values.empty()) {
    Vec3 lo = values[0], hi = values[0];
    for (const Vec3& v : values) {
      lo = Vec3(std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z));
      hi = Vec3(std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z));
    }
    accessor.minValues = {lo.x, lo.y, lo.z};
    accessor.maxValues = {hi.x, hi.y, hi.z};
  }
  model.accessors.push_back(accessor);
  return int(model.accessors.size() - 1);
}

// Indices as 16-bit integers when every vertex fits (a quarter less to send and to hash for
// typical results of up to ~130K triangles); 65535 is glTF's primitive-restart value and may not
// be used, so 16 bits hold at most 65535 vertices.
bool fitsShortIndices(const TriangleMesh& mesh) { return mesh.positions.size() <= 65535; }

void appendIndices(std::vector<unsigned char>& buffer, const TriangleMesh& mesh) {
  if (!fitsShortIndices(mesh)) {
    appendBytes(buffer, mesh.indices);
    return;
  }
  const size_t offset = buffer.size();
  // GLB chunks end on a 4-byte boundary; the padding is zeros.
  buffer.resize((offset + mesh.indices.size() * sizeof(uint16_t) + 3) & ~size_t(3));
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    const uint16_t index = static_cast<uint16_t>(mesh.indices[i]);
    std::memcpy(buffer.data() + offset + i * sizeof(uint16_t), &index, sizeof index);
  }
}

int addIndexAccessor(tinygltf::Model& model, size_t offset, const TriangleMesh& mesh) {
  const bool shortIndices = fitsShortIndices(mesh);
  const size_t elementBytes = shortIndices ? sizeof(uint16_t) : sizeof(uint32_t);
  tinygltf::Accessor indices;
  indices.bufferView = addView(model, offset, mesh.indices.size() * elementBytes,
                               TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  indices.componentType =
      shortIndices ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  indices.type = TINYGLTF_TYPE_SCALAR;
  indices.count = mesh.indices.size();
  model.accessors.push_back(indices);
  return int(model.accessors.size() - 1);
}

}  // namespace

std::vector<uint8_t> writeGlb(const TriangleMesh& mesh, const std::string& meshName) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Tessera";
  tinygltf::Buffer buffer;
  appendBytes(buffer.data, mesh.positions);
  appendBytes(buffer.data, mesh.normals);
  appendIndices(buffer.data, mesh);
  model.buffers.push_back(buffer);

  const size_t vertexBytes = mesh.positions.size() * sizeof(Vec3);
  int positions = addVec3Accessor(model, addView(model, 0, vertexBytes, TINYGLTF_TARGET_ARRAY_BUFFER),
                                  mesh.positions, true);
  int normals = addVec3Accessor(model, addView(model, vertexBytes, vertexBytes, TINYGLTF_TARGET_ARRAY_BUFFER),
                                mesh.normals, false);
  int indices = addIndexAccessor(model, 2 * vertexBytes, mesh);

  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = positions;
  primitive.attributes["NORMAL"] = normals;
  primitive.indices = indices;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh gltfMesh;
  gltfMesh.name = meshName;
  gltfMesh.primitives.push_back(primitive);
  model.meshes.push_back(gltfMesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = meshName;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, out, false, true)) throwInvalid("could not write the GLB");
  std::string bytes = out.str();
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
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
