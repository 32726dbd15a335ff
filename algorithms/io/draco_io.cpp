// Draco (.drc) and glTF (.glb, .gltf) through Google's Draco library, whose
// transcoder also writes and reads glTF 2.0: one well-kept implementation
// instead of a hand-written glTF writer.
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/io/gltf_decoder.h>
#include <draco/io/gltf_encoder.h>
#include <draco/mesh/mesh.h>

#include "core/errors.h"
#include "io/readers.h"

namespace cgview::detail {

namespace {

// A draco::Mesh with one point per vertex (attributes made per vertex first).
std::unique_ptr<draco::Mesh> to_draco(const Mesh& input) {
  const Mesh mesh = with_per_vertex_attributes(input);
  auto out = std::make_unique<draco::Mesh>();
  const std::size_t n = mesh.num_vertices();
  out->set_num_points(draco::PointIndex::ValueType(n));
  auto add = [&](draco::GeometryAttribute::Type type, int components, draco::DataType dt, bool normalized,
                 int bytes_each) {
    draco::GeometryAttribute ga;
    ga.Init(type, nullptr, std::uint8_t(components), dt, normalized, bytes_each * components, 0);
    const int id = out->AddAttribute(ga, true, draco::AttributeValueIndex::ValueType(n));
    return out->attribute(id);
  };
  draco::PointAttribute* pos = add(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32, false, 4);
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3f p = to_float(mesh.positions[v]);
    const float xyz[3] = {p.x, p.y, p.z};
    pos->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(v)), xyz);
  }
  if (mesh.has_normals()) {
    draco::PointAttribute* nrm = add(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32, false, 4);
    for (std::size_t v = 0; v < n; ++v) {
      const Vec3f q = normalized(mesh.normals[v]);
      const float xyz[3] = {q.x, q.y, q.z};
      nrm->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(v)), xyz);
    }
  }
  if (mesh.has_uvs()) {
    draco::PointAttribute* tex = add(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32, false, 4);
    for (std::size_t v = 0; v < n; ++v) {
      const float uv[2] = {mesh.uvs[v].u, mesh.uvs[v].v};
      tex->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(v)), uv);
    }
  }
  if (mesh.has_colors()) {
    draco::PointAttribute* col = add(draco::GeometryAttribute::COLOR, 4, draco::DT_UINT8, true, 1);
    for (std::size_t v = 0; v < n; ++v) {
      const Color c = mesh.colors[v];
      const std::uint8_t rgba[4] = {c.r, c.g, c.b, c.a};
      col->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(v)), rgba);
    }
  }
  out->SetNumFaces(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Tri& t = mesh.faces[f];
    out->SetFace(draco::FaceIndex(draco::FaceIndex::ValueType(f)),
                 {draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
  }
  return out;
}

// Our Mesh from a decoded draco::Mesh: one vertex per draco point.
void from_draco(const draco::Mesh& dm, const std::string& name, ReadResult& result) {
  Mesh& mesh = result.mesh;
  const draco::PointAttribute* pos = dm.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!pos) throw ParseError(name, "the Draco data has no positions", std::nullopt, std::nullopt);
  const std::size_t n = dm.num_points();
  mesh.positions.resize(n);
  const draco::PointAttribute* nrm = dm.GetNamedAttribute(draco::GeometryAttribute::NORMAL);
  const draco::PointAttribute* tex = dm.GetNamedAttribute(draco::GeometryAttribute::TEX_COORD);
  const draco::PointAttribute* col = dm.GetNamedAttribute(draco::GeometryAttribute::COLOR);
  if (nrm) mesh.normals.resize(n);
  if (tex) mesh.uvs.resize(n);
  if (col) mesh.colors.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const draco::PointIndex p(static_cast<draco::PointIndex::ValueType>(i));
    float xyz[3] = {0, 0, 0};
    pos->ConvertValue<float>(pos->mapped_index(p), 3, xyz);
    mesh.positions[i] = {xyz[0], xyz[1], xyz[2]};
    if (nrm) {
      nrm->ConvertValue<float>(nrm->mapped_index(p), 3, xyz);
      mesh.normals[i] = {xyz[0], xyz[1], xyz[2]};
    }
    if (tex) {
      float uv[2] = {0, 0};
      tex->ConvertValue<float>(tex->mapped_index(p), 2, uv);
      mesh.uvs[i] = {uv[0], uv[1]};
    }
    if (col) {
      float rgba[4] = {1, 1, 1, 1};
      col->ConvertValue<float>(col->mapped_index(p), std::int8_t(std::min<int>(4, col->num_components())), rgba);
      auto byte = [&](float x) {
        const float scale = col->normalized() || col->data_type() == draco::DT_FLOAT32 ? 255.f : 1.f;
        return std::uint8_t(std::clamp(std::lround(x * scale), 0L, 255L));
      };
      mesh.colors[i] = {byte(rgba[0]), byte(rgba[1]), byte(rgba[2]),
                        col->num_components() >= 4 ? byte(rgba[3]) : std::uint8_t(255)};
    }
  }
  mesh.faces.resize(dm.num_faces());
  for (std::size_t f = 0; f < dm.num_faces(); ++f) {
    const auto& face = dm.face(draco::FaceIndex(static_cast<draco::FaceIndex::ValueType>(f)));
    mesh.faces[f] = {face[0].value(), face[1].value(), face[2].value()};
  }
}

std::string to_string(const draco::EncoderBuffer& buf) { return std::string(buf.data(), buf.size()); }

}  // namespace

void read_draco(std::string_view bytes, const std::string& name, ReadResult& result) {
  if (bytes.empty()) throw ParseError(name, "the file is empty", std::nullopt, std::nullopt);
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) throw ParseError(name, "not a Draco file: " + type.status().error_msg_string(), std::nullopt, 0);
  if (type.value() != draco::TRIANGULAR_MESH)
    throw ParseError(name, "the Draco file holds a point cloud, not a triangle mesh", std::nullopt, 0);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok())
    throw ParseError(name, "Draco could not decode it: " + decoded.status().error_msg_string(), std::nullopt, std::nullopt);
  from_draco(*decoded.value(), name, result);
}

void read_gltf(std::string_view bytes, const std::string& name, bool binary, ReadResult& result) {
  if (bytes.empty()) throw ParseError(name, "the file is empty", std::nullopt, std::nullopt);
  if (binary && !bytes.starts_with("glTF")) throw ParseError(name, "not a glTF binary file: no 'glTF' magic", std::nullopt, 0);
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  draco::GltfDecoder decoder;
  auto decoded = decoder.DecodeFromBuffer(&buffer);
  if (!decoded.ok())
    throw ParseError(name, "the glTF reader failed: " + decoded.status().error_msg_string(), std::nullopt, std::nullopt);
  from_draco(*decoded.value(), name, result);
}

std::string write_draco(const Mesh& mesh, const WriteOptions& options) {
  auto dm = to_draco(mesh);
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.position_bits);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, options.normal_bits);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, options.uv_bits);
  const int speed = std::clamp(options.draco_speed, 0, 10);
  encoder.SetSpeedOptions(speed, speed);
  draco::EncoderBuffer buf;
  const draco::Status s = encoder.EncodeMeshToBuffer(*dm, &buf);
  if (!s.ok()) throw Error("Draco could not encode the mesh: " + s.error_msg_string());
  return to_string(buf);
}

std::string write_glb(const Mesh& mesh) {
  auto dm = to_draco(mesh);
  draco::GltfEncoder encoder;
  draco::EncoderBuffer buf;
  const draco::Status s = encoder.EncodeToBuffer(*dm, &buf);
  if (!s.ok()) throw Error("the glTF writer failed: " + s.error_msg_string());
  return to_string(buf);
}

}  // namespace cgview::detail
