#include "core/mesh/mesh_codec.h"

#include <bit>
#include <cstdint>

#include "core/mesh/subdivision_rules.h"

namespace tessera {
namespace {

constexpr std::string_view kMagic = "TSM1";
constexpr std::string_view kUvsTag = "UVS1";
constexpr std::string_view kOriginTag = "ORG1";

class Writer {
 public:
  void bytes(std::string_view b) { out_.append(b); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) out_ += static_cast<char>((v >> (8 * i)) & 0xff);
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) out_ += static_cast<char>((v >> (8 * i)) & 0xff);
  }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void f32(float v) { u32(std::bit_cast<uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<uint64_t>(v)); }
  void reserve(size_t n) { out_.reserve(n); }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}

  std::string_view bytes(size_t n) {
    need(n);
    std::string_view b = in_.substr(pos_, n);
    pos_ += n;
    return b;
  }
  uint32_t u32() {
    need(4);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(uint8_t(in_[pos_ + i])) << (8 * i);
    pos_ += 4;
    return v;
  }
  uint64_t u64() {
    need(8);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(uint8_t(in_[pos_ + i])) << (8 * i);
    pos_ += 8;
    return v;
  }
  int32_t i32() { return static_cast<int32_t>(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  double f64() { return std::bit_cast<double>(u64()); }
  // Whether the next bytes are `tag` (nothing is read).
  bool peek(std::string_view tag) const { return in_.substr(pos_, tag.size()) == tag; }

  // A count of records of recordBytes each that must fit in what is left: checked before any
  // allocation, so a corrupt count cannot make the decoder reserve terabytes.
  size_t count(size_t recordBytes) {
    uint64_t n = u64();
    if (n > (in_.size() - pos_) / recordBytes)
      throw MeshDecodeError("mesh encoding: count too large");
    return static_cast<size_t>(n);
  }
  bool atEnd() const { return pos_ == in_.size(); }

 private:
  void need(size_t n) const {
    if (in_.size() - pos_ < n) throw MeshDecodeError("mesh encoding: truncated");
  }
  std::string_view in_;
  size_t pos_ = 0;
};

SubdivisionRules rulesFrom(uint32_t code) {
  const std::optional<SubdivisionRules> rules = rulesFromCode(code);
  if (!rules) throw MeshDecodeError("mesh encoding: unknown subdivision rules");
  return *rules;
}

}  // namespace

std::string encodeCanonicalMesh(const ControlMesh& mesh) {
  Writer w;
  w.reserve(kMagic.size() + 4 + 6 * 8 + 12 * mesh.positions.size() + 4 * mesh.faceSizes.size() +
            4 * mesh.faceVertices.size() + 12 * mesh.creases.size() + 8 * mesh.corners.size() +
            4 * mesh.holes.size() + 16 + 4 * mesh.uvs.size() + 4 * mesh.uvIndices.size());
  w.bytes(kMagic);
  w.u32(rulesCode(mesh.rules));
  w.u64(mesh.positions.size());
  for (const Vec3& p : mesh.positions) {
    w.f32(p.x), w.f32(p.y), w.f32(p.z);
  }
  w.u64(mesh.faceSizes.size());
  for (int n : mesh.faceSizes) w.i32(n);
  w.u64(mesh.faceVertices.size());
  for (int v : mesh.faceVertices) w.i32(v);
  w.u64(mesh.creases.size());
  for (const CreaseEdge& c : mesh.creases) {
    w.i32(c.v0), w.i32(c.v1), w.f32(c.sharpness);
  }
  w.u64(mesh.corners.size());
  for (const CornerVertex& c : mesh.corners) {
    w.i32(c.vertex), w.f32(c.sharpness);
  }
  w.u64(mesh.holes.size());
  for (int f : mesh.holes) w.i32(f);
  // Optional sections, each only when the mesh has it (so meshes without keep the encoding and
  // sha256 they had), named by a tag, in this order.
  if (mesh.hasUvs()) {
    w.bytes(kUvsTag);
    w.u64(mesh.uvs.size());
    for (float c : mesh.uvs) w.f32(c);
    w.u64(mesh.uvIndices.size());
    for (int i : mesh.uvIndices) w.i32(i);
  }
  if (mesh.hasOrigin()) {
    w.bytes(kOriginTag);
    w.f64(mesh.origin.x), w.f64(mesh.origin.y), w.f64(mesh.origin.z);
  }
  return w.take();
}

ControlMesh decodeCanonicalMesh(std::string_view bytes) {
  Reader r(bytes);
  if (r.bytes(kMagic.size()) != kMagic) throw MeshDecodeError("mesh encoding: bad magic");
  ControlMesh mesh;
  mesh.rules = rulesFrom(r.u32());
  mesh.positions.resize(r.count(12));
  for (Vec3& p : mesh.positions) {
    p.x = r.f32(), p.y = r.f32(), p.z = r.f32();
  }
  mesh.faceSizes.resize(r.count(4));
  for (int& n : mesh.faceSizes) n = r.i32();
  mesh.faceVertices.resize(r.count(4));
  for (int& v : mesh.faceVertices) v = r.i32();
  mesh.creases.resize(r.count(12));
  for (CreaseEdge& c : mesh.creases) {
    c.v0 = r.i32(), c.v1 = r.i32(), c.sharpness = r.f32();
  }
  mesh.corners.resize(r.count(8));
  for (CornerVertex& c : mesh.corners) {
    c.vertex = r.i32(), c.sharpness = r.f32();
  }
  mesh.holes.resize(r.count(4));
  for (int& f : mesh.holes) f = r.i32();
  if (!r.atEnd() && r.peek(kUvsTag)) {
    r.bytes(kUvsTag.size());
    mesh.uvs.resize(r.count(4));
    for (float& c : mesh.uvs) c = r.f32();
    mesh.uvIndices.resize(r.count(4));
    for (int& i : mesh.uvIndices) i = r.i32();
  }
  if (!r.atEnd() && r.peek(kOriginTag)) {
    r.bytes(kOriginTag.size());
    mesh.origin.x = r.f64(), mesh.origin.y = r.f64(), mesh.origin.z = r.f64();
  }
  if (!r.atEnd()) throw MeshDecodeError("mesh encoding: trailing bytes");
  return mesh;
}

size_t meshHeapBytes(const ControlMesh& mesh) {
  return sizeof(ControlMesh) + mesh.positions.capacity() * sizeof(Vec3) +
         mesh.faceSizes.capacity() * sizeof(int) + mesh.faceVertices.capacity() * sizeof(int) +
         mesh.creases.capacity() * sizeof(CreaseEdge) +
         mesh.corners.capacity() * sizeof(CornerVertex) + mesh.holes.capacity() * sizeof(int) +
         mesh.uvs.capacity() * sizeof(float) + mesh.uvIndices.capacity() * sizeof(int);
}

}  // namespace tessera
