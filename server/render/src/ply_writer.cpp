#include "semfuse/render/ply_writer.hpp"

#include <cstring>

namespace semfuse::render {
namespace {

// Appends values in little-endian byte order whatever the host order is.
class LittleEndianWriter {
 public:
  explicit LittleEndianWriter(std::string& out) : out_(out) {}
  void u8(uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u16(uint16_t v) { bytes(v, 2); }
  void i32(int32_t v) { bytes(static_cast<uint32_t>(v), 4); }
  void f32(float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    bytes(bits, 4);
  }

 private:
  void bytes(uint32_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
  }
  std::string& out_;
};

Status checkMesh(const LabeledMesh& mesh, const PlyOptions& options) {
  const size_t n = mesh.vertices.size();
  if (mesh.labels.size() != n || mesh.scores.size() != n)
    return makeError("mesh labels/scores do not match its " + std::to_string(n) + " vertices");
  if (options.normals && mesh.normals.size() != n)
    return makeError("mesh normals do not match its " + std::to_string(n) + " vertices");
  if (options.color == PlyColor::kVoxelColor && mesh.colors.size() != n)
    return makeError("voxel colours requested but the mesh has " + std::to_string(mesh.colors.size()) +
                     " colours for " + std::to_string(n) + " vertices");
  if (n > static_cast<size_t>(INT32_MAX)) return makeError("mesh has too many vertices for PLY int indices");
  for (size_t f = 0; f < mesh.triangles.size(); ++f)
    for (uint32_t index : mesh.triangles[f])
      if (index >= n)
        return makeError("mesh triangle " + std::to_string(f) + " indexes vertex " + std::to_string(index) + " of " +
                         std::to_string(n));
  return Status::Ok();
}

std::string header(const LabeledMesh& mesh, const PlyOptions& options) {
  std::string h = "ply\nformat binary_little_endian 1.0\ncomment semfuse labeled mesh\n";
  h += "element vertex " + std::to_string(mesh.vertices.size()) + "\n";
  h += "property float x\nproperty float y\nproperty float z\n";
  if (options.normals) h += "property float nx\nproperty float ny\nproperty float nz\n";
  h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  h += "property ushort label\nproperty float score\n";
  h += "element face " + std::to_string(mesh.triangles.size()) + "\n";
  h += "property list uchar int vertex_indices\nend_header\n";
  return h;
}

}  // namespace

Result<std::string> plyBytes(const LabeledMesh& mesh, const LabelLegend& legend, const PlyOptions& options) {
  if (Status ok = checkMesh(mesh, options); !ok) return makeError(ok.error());
  std::string out = header(mesh, options);
  const size_t vertex_bytes = 12 + (options.normals ? 12 : 0) + 3 + 2 + 4;
  out.reserve(out.size() + mesh.vertices.size() * vertex_bytes + mesh.triangles.size() * 13);
  LittleEndianWriter w(out);
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int a = 0; a < 3; ++a) w.f32(mesh.vertices[i][a]);
    if (options.normals)
      for (int a = 0; a < 3; ++a) w.f32(mesh.normals[i][a]);
    if (options.color == PlyColor::kVoxelColor) {
      w.u8(mesh.colors[i].r);
      w.u8(mesh.colors[i].g);
      w.u8(mesh.colors[i].b);
    } else {
      for (uint8_t c : legend.colorOf(mesh.labels[i])) w.u8(c);
    }
    w.u16(mesh.labels[i]);
    w.f32(mesh.scores[i]);
  }
  for (const auto& t : mesh.triangles) {
    w.u8(3);
    for (uint32_t index : t) w.i32(static_cast<int32_t>(index));
  }
  return out;
}

}  // namespace semfuse::render
