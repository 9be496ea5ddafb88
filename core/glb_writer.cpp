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

}  // namespace

std::vector<uint8_t> writeGlb(const TriangleMesh& mesh, const std::string& meshName) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Tessera";
  tinygltf::Buffer buffer;
  appendBytes(buffer.data, mesh.positions);
  appendBytes(buffer.data, mesh.normals);
  appendBytes(buffer.data, mesh.indices);
  model.buffers.push_back(buffer);

  const size_t vertexBytes = mesh.positions.size() * sizeof(Vec3);
  int positions = addVec3Accessor(model, addView(model, 0, vertexBytes, TINYGLTF_TARGET_ARRAY_BUFFER),
                                  mesh.positions, true);
  int normals = addVec3Accessor(model, addView(model, vertexBytes, vertexBytes, TINYGLTF_TARGET_ARRAY_BUFFER),
                                mesh.normals, false);
  tinygltf::Accessor indices;
  indices.bufferView = addView(model, 2 * vertexBytes, mesh.indices.size() * sizeof(uint32_t),
                               TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  indices.type = TINYGLTF_TYPE_SCALAR;
  indices.count = mesh.indices.size();
  model.accessors.push_back(indices);

  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = positions;
  primitive.attributes["NORMAL"] = normals;
  primitive.indices = int(model.accessors.size() - 1);
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

TriangleMesh readGlb(const std::vector<uint8_t>& bytes) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  if (!loader.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(), unsigned(bytes.size()))) {
    throwInvalid("not a readable GLB: " + error);
  }
  if (model.meshes.size() != 1 || model.meshes[0].primitives.size() != 1) throwInvalid("expected one primitive");
  const auto& primitive = model.meshes[0].primitives[0];
  auto accessorData = [&](int index, size_t elementSize) {
    const auto& accessor = model.accessors.at(index);
    const auto& view = model.bufferViews.at(accessor.bufferView);
    const auto& buffer = model.buffers.at(view.buffer);
    const unsigned char* start = buffer.data.data() + view.byteOffset + accessor.byteOffset;
    return std::make_pair(start, accessor.count * elementSize);
  };
  TriangleMesh mesh;
  auto [positionData, positionBytes] = accessorData(primitive.attributes.at("POSITION"), sizeof(Vec3));
  mesh.positions.resize(positionBytes / sizeof(Vec3));
  std::memcpy(mesh.positions.data(), positionData, positionBytes);
  auto [normalData, normalBytes] = accessorData(primitive.attributes.at("NORMAL"), sizeof(Vec3));
  mesh.normals.resize(normalBytes / sizeof(Vec3));
  std::memcpy(mesh.normals.data(), normalData, normalBytes);
  auto [indexData, indexBytes] = accessorData(primitive.indices, sizeof(uint32_t));
  mesh.indices.resize(indexBytes / sizeof(uint32_t));
  std::memcpy(mesh.indices.data(), indexData, indexBytes);
  return mesh;
}

}  // namespace tessera
