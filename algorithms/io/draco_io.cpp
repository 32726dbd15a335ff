// Draco (.drc) through Google's Draco library, and glTF binary written by
// Draco's transcoder (one well-kept implementation instead of a hand-written
// glTF writer); the glTF reader is gltf_io.cpp.
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/io/gltf_encoder.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <deque>
#include <map>
#include <numeric>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <unordered_map>

#include "core/errors.h"
#include "io/draco_io.h"
#include "io/materials.h"
#include "io/parse_json.h"
#include "io/readers.h"

namespace cgview::detail {

namespace {

// The GENERIC attribute with each point's vertex in the written mesh (draco_stored_order).
constexpr const char* kVertexIdAttribute = "vertex_id";

// A draco::Mesh with one point per vertex (attributes made per vertex
// first), or, given each face's material, one point per (vertex, material)
// pair: a vertex on a material boundary becomes one point per material, all
// pointing at the vertex's attribute values, and a GENERIC attribute named
// kDracoMaterialAttribute holds each point's material.
std::unique_ptr<draco::Mesh> to_draco(const Mesh& input, std::span<const std::uint32_t> face_material = {},
                                      bool stored_ids = false) {
  const Mesh mesh = with_per_vertex_attributes(input);
  if (!face_material.empty() && face_material.size() != mesh.num_faces())
    throw InvalidInput("the material list has " + std::to_string(face_material.size()) + " faces, the mesh " +
                       std::to_string(mesh.num_faces()));
  auto out = std::make_unique<draco::Mesh>();
  const std::size_t n = mesh.num_vertices();
  std::vector<std::uint32_t> point_vertex, point_material;
  std::vector<std::array<std::uint32_t, 3>> face_points(mesh.num_faces());
  if (face_material.empty()) {
    for (std::size_t f = 0; f < mesh.num_faces(); ++f)
      face_points[f] = {std::uint32_t(mesh.faces[f][0]), std::uint32_t(mesh.faces[f][1]),
                        std::uint32_t(mesh.faces[f][2])};
  } else {
    std::unordered_map<std::uint64_t, std::uint32_t> point_of;
    for (std::size_t f = 0; f < mesh.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t v = mesh.faces[f][k];
        const auto [it, fresh] = point_of.try_emplace(v << 32 | face_material[f], std::uint32_t(point_vertex.size()));
        if (fresh) {
          point_vertex.push_back(std::uint32_t(v));
          point_material.push_back(face_material[f]);
        }
        face_points[f][k] = it->second;
      }
  }
  const bool identity = face_material.empty();
  out->set_num_points(draco::PointIndex::ValueType(identity ? n : point_vertex.size()));
  auto add = [&](draco::GeometryAttribute::Type type, int components, draco::DataType dt, bool normalized,
                 int bytes_each, std::size_t values) {
    draco::GeometryAttribute ga;
    ga.Init(type, nullptr, std::uint8_t(components), dt, normalized, bytes_each * components, 0);
    const int id = out->AddAttribute(ga, identity, draco::AttributeValueIndex::ValueType(values));
    draco::PointAttribute* a = out->attribute(id);
    if (!identity)
      for (std::size_t p = 0; p < point_vertex.size(); ++p)
        a->SetPointMapEntry(draco::PointIndex(draco::PointIndex::ValueType(p)),
                            draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(
                                type == draco::GeometryAttribute::GENERIC ? point_material[p] : point_vertex[p])));
    return a;
  };
  draco::PointAttribute* pos = add(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32, false, 4, n);
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3f p = to_float(mesh.positions[v]);
    const float xyz[3] = {p.x, p.y, p.z};
    pos->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(v)), xyz);
  }
  if (mesh.has_normals()) {
    draco::PointAttribute* nrm = add(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32, false, 4, n);
    for (std::size_t v = 0; v < n; ++v) {
      const Vec3f q = normalized(mesh.normals[v]);
      const float xyz[3] = {q.x, q.y, q.z};
      nrm->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(v)), xyz);
    }
  }
  if (mesh.has_uvs()) {
    draco::PointAttribute* tex = add(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32, false, 4, n);
    for (std::size_t v = 0; v < n; ++v) {
      const float uv[2] = {mesh.uvs[v].u, mesh.uvs[v].v};
      tex->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(v)), uv);
    }
  }
  if (mesh.has_colors()) {
    draco::PointAttribute* col = add(draco::GeometryAttribute::COLOR, 4, draco::DT_UINT8, true, 1, n);
    for (std::size_t v = 0; v < n; ++v) {
      const Color c = mesh.colors[v];
      const std::uint8_t rgba[4] = {c.r, c.g, c.b, c.a};
      col->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(v)), rgba);
    }
  }
  if (!identity) {
    const std::uint32_t materials = *std::max_element(face_material.begin(), face_material.end()) + 1;
    draco::PointAttribute* mat = add(draco::GeometryAttribute::GENERIC, 1, draco::DT_UINT32, false, 4, materials);
    for (std::uint32_t m = 0; m < materials; ++m) mat->SetAttributeValue(draco::AttributeValueIndex(m), &m);
    auto metadata = std::make_unique<draco::AttributeMetadata>();
    metadata->AddEntryString("name", kDracoMaterialAttribute);
    metadata->set_att_unique_id(mat->unique_id());
    out->AddAttributeMetadata(out->num_attributes() - 1, std::move(metadata));
  }
  if (stored_ids) {
    // with_per_vertex_attributes keeps the faces and their corners in order:
    // a corner names the input's vertex its new vertex was made from.
    std::vector<std::uint32_t> vertex_of(n);
    if (input.attributes_per_vertex()) std::iota(vertex_of.begin(), vertex_of.end(), 0u);
    else
      for (std::size_t f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) vertex_of[mesh.faces[f][k]] = std::uint32_t(input.faces[f][k]);
    const std::size_t points = out->num_points();
    draco::GeometryAttribute ga;
    ga.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_UINT32, false, 4, 0);
    draco::PointAttribute* ids =
        out->attribute(out->AddAttribute(ga, true, draco::AttributeValueIndex::ValueType(points)));
    for (std::size_t p = 0; p < points; ++p) {
      const std::uint32_t v = vertex_of[identity ? p : point_vertex[p]];
      ids->SetAttributeValue(draco::AttributeValueIndex(draco::AttributeValueIndex::ValueType(p)), &v);
    }
    auto metadata = std::make_unique<draco::AttributeMetadata>();
    metadata->AddEntryString("name", kVertexIdAttribute);
    metadata->set_att_unique_id(ids->unique_id());
    out->AddAttributeMetadata(out->num_attributes() - 1, std::move(metadata));
  }
  out->SetNumFaces(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto& t = face_points[f];
    out->SetFace(draco::FaceIndex(draco::FaceIndex::ValueType(f)),
                 {draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
  }
  return out;
}

}  // namespace

// Draco converts a bool attribute by loading its bytes as bool, undefined
// for any byte but 0 and 1 (the fuzzer's first finding): positions,
// normals, texture coordinates and colours are numbers, so any other type
// is refused.
const draco::PointAttribute* numeric_draco_attribute(const draco::PointAttribute* a, const std::string& name,
                                                     const char* what) {
  if (!a) return nullptr;
  const draco::DataType t = a->data_type();
  if (t < draco::DT_INT8 || t > draco::DT_FLOAT64)
    throw ParseError(name,
                     std::string("the Draco ") + what + " are of data type " + std::to_string(int(t)) + ", not numbers",
                     std::nullopt, std::nullopt);
  return a;
}

namespace {

// Our Mesh from a decoded draco::Mesh, or draco::PointCloud (no faces): one
// vertex per draco point.
void from_draco(const draco::PointCloud& dm, const draco::Mesh* faces, const std::string& name, ReadResult& result) {
  Mesh& mesh = result.mesh;
  const draco::PointAttribute* pos =
      numeric_draco_attribute(dm.GetNamedAttribute(draco::GeometryAttribute::POSITION), name, "positions");
  if (!pos) throw ParseError(name, "the Draco data has no positions", std::nullopt, std::nullopt);
  const std::size_t n = dm.num_points();
  mesh.positions.resize(n);
  const draco::PointAttribute* nrm =
      numeric_draco_attribute(dm.GetNamedAttribute(draco::GeometryAttribute::NORMAL), name, "normals");
  const draco::PointAttribute* tex =
      numeric_draco_attribute(dm.GetNamedAttribute(draco::GeometryAttribute::TEX_COORD), name, "texture coordinates");
  const draco::PointAttribute* col =
      numeric_draco_attribute(dm.GetNamedAttribute(draco::GeometryAttribute::COLOR), name, "colours");
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
  if (!faces) return;
  mesh.faces.resize(faces->num_faces());
  for (std::size_t f = 0; f < faces->num_faces(); ++f) {
    const auto& face = faces->face(draco::FaceIndex(static_cast<draco::FaceIndex::ValueType>(f)));
    mesh.faces[f] = {face[0].value(), face[1].value(), face[2].value()};
  }
}

std::string to_string(const draco::EncoderBuffer& buf) { return std::string(buf.data(), buf.size()); }

// The counts a Draco mesh's connectivity header claims, read as Draco 1.5's
// decoder reads them (header, metadata, edgebreaker's traversal byte, then
// the counts: uint32s before bitstream 2.0, varints after).
struct DracoClaims {
  bool edgebreaker = false, point_cloud = false;
  std::uint64_t faces = 0, vertices = 0;
  // A point cloud's: its points, and the components of their attributes
  // (3 for positions, ...), summed over those its header declares.
  std::uint64_t points = 0, components = 0;
  // A kd-tree point cloud of a bitstream before 2.3 (Draco before 1.3)
  // carries a second count of points, which Draco's backward-compatible
  // decoder allocates for unchecked.
  bool old_kd_tree = false;
};

class DracoHeaderReader {
 public:
  explicit DracoHeaderReader(std::string_view b) : b_(b) {}
  bool byte(std::uint8_t& v) {
    if (at_ >= b_.size()) return false;
    v = std::uint8_t(b_[at_++]);
    return true;
  }
  bool skip(std::uint64_t n) {
    if (n > b_.size() - at_) return false;
    at_ += std::size_t(n);
    return true;
  }
  bool varint(std::uint64_t& v) {
    v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
      std::uint8_t c;
      if (!byte(c)) return false;
      v |= std::uint64_t(c & 0x7f) << shift;
      if (!(c & 0x80)) return true;
    }
    return false;
  }
  bool u32(std::uint64_t& v) {
    if (b_.size() - at_ < 4) return false;
    const auto* u = reinterpret_cast<const unsigned char*>(b_.data() + at_);
    v = std::uint32_t(u[0]) | std::uint32_t(u[1]) << 8 | std::uint32_t(u[2]) << 16 | std::uint32_t(u[3]) << 24;
    at_ += 4;
    return true;
  }
  // A metadata block and its sub-blocks, depth first, as MetadataDecoder reads them.
  bool metadata() {
    for (std::uint64_t pending = 1, first = 1; pending > 0; --pending, first = 0) {
      std::uint8_t len;
      if (!first && (!byte(len) || !skip(len))) return false;  // a sub-block's name
      std::uint64_t entries, subs;
      if (!varint(entries)) return false;
      for (std::uint64_t e = 0; e < entries; ++e) {
        std::uint64_t size;
        if (!byte(len) || !skip(len) || !varint(size) || !skip(size)) return false;
      }
      if (!varint(subs) || subs > b_.size() - at_) return false;
      pending += subs;
    }
    return true;
  }

 private:
  std::string_view b_;
  std::size_t at_ = 0;
};

// nullopt when the bytes end inside the header (Draco's decoder says what is wrong then).
std::optional<DracoClaims> draco_claims(std::string_view bytes) {
  DracoHeaderReader r(bytes);
  std::uint8_t major, minor, type, method, flags_lo, flags_hi;
  if (!r.skip(5) || !r.byte(major) || !r.byte(minor) || !r.byte(type) || !r.byte(method) || !r.byte(flags_lo) ||
      !r.byte(flags_hi))
    return std::nullopt;
  const int version = major * 256 + minor;
  if (version >= 0x0103 && (flags_hi & 0x80)) {  // METADATA_FLAG_MASK 0x8000
    std::uint64_t attributes, id;
    if (!r.varint(attributes)) return std::nullopt;
    for (std::uint64_t i = 0; i < attributes; ++i)
      if (!r.varint(id) || !r.metadata()) return std::nullopt;
    if (!r.metadata()) return std::nullopt;
  }
  DracoClaims c;
  if (type == draco::POINT_CLOUD) {
    // Both of its methods (sequential, kd-tree) start with the count as an
    // int32; then the attribute decoders, each with its attributes (type,
    // data type, components, normalized, id), which the bytes must hold
    // before any is decoded (a count cut short is claimed as far as it goes).
    c.point_cloud = true;
    c.old_kd_tree = method == 1 && version < 0x0203;  // POINT_CLOUD_KD_TREE_ENCODING
    if (!r.u32(c.points)) return std::nullopt;
    std::uint8_t decoders;
    if (!r.byte(decoders)) return c;
    for (int d = 0; d < decoders; ++d) {
      std::uint64_t attributes, id;
      if (!(version < 0x0200 ? r.u32(attributes) : r.varint(attributes))) return c;
      for (std::uint64_t a = 0; a < attributes; ++a) {
        std::uint8_t att_type, data_type, components, normalized;
        if (!r.byte(att_type) || !r.byte(data_type) || !r.byte(components) || !r.byte(normalized) ||
            !(version < 0x0103 ? r.skip(2) : r.varint(id)))
          return c;
        c.components += components;
      }
    }
    return c;
  }
  auto count = [&](std::uint64_t& v) { return version < 0x0200 ? r.u32(v) : r.varint(v); };
  c.edgebreaker = method == 1;
  if (c.edgebreaker) {
    std::uint8_t traversal;
    std::uint64_t new_vertices;
    if (!r.byte(traversal)) return std::nullopt;
    if (version < 0x0202 && !count(new_vertices)) return std::nullopt;
    if (!count(c.vertices) || !count(c.faces)) return std::nullopt;
  } else {
    if (!(version < 0x0202 ? r.u32(c.faces) && r.u32(c.vertices) : r.varint(c.faces) && r.varint(c.vertices)))
      return std::nullopt;
  }
  return c;
}

// Draco quantizes float positions over their box, texture coordinates too,
// and normals as unit floats: a coordinate past a float's range (1e308 in a
// text file, valid as a double) or a box wider than one has no float, and
// Draco fails on it.  Refused, naming the first.
void check_float_range(const Mesh& mesh) {
  std::array<float, 3> lo{}, hi{};
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3f p = to_float(mesh.positions[v]);
    for (int a = 0; a < 3; ++a) {
      lo[a] = v == 0 ? p[a] : std::min(lo[a], p[a]);
      hi[a] = v == 0 ? p[a] : std::max(hi[a], p[a]);
    }
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(hi[0] - lo[0]) ||
        !std::isfinite(hi[1] - lo[1]) || !std::isfinite(hi[2] - lo[2]))
      throw InvalidInput("vertex " + std::to_string(v) +
                         " lies beyond the range of a float (3.4e38), which Draco needs");
  }
  for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
    const Vec3f n = mesh.normals[i];
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
      throw InvalidInput("normal " + std::to_string(i) + " is not finite");
  }
  for (std::size_t i = 0; i < mesh.uvs.size(); ++i)
    if (!std::isfinite(mesh.uvs[i].u) || !std::isfinite(mesh.uvs[i].v))
      throw InvalidInput("texture coordinate " + std::to_string(i) + " is not finite");
}

}  // namespace

// Draco's edgebreaker decoder sizes its corner table from the face count the
// header claims (up to 1.4 billion: tens of GB) before any byte backs it; the
// sequential one checks the count against the bytes left.  Refused here when
// the claim is more than kDracoFacesPerByte faces a byte of the stream, with
// a million faces always allowed.  Measured with Draco 1.5.5 at its best
// compression: scanned meshes hold 0.6-1.2 faces a byte at 14-bit positions
// and up to 12 at 4 bits; a regular grid, whose every vertex is predicted
// exactly, 6.5 at 14 bits, 115 at 4 and 715 (3.9 million faces) at 1 bit
// (test TheDensestHonestDracoStreamIsUnderTheBoundAndLoads).  A bigger file
// whose claim passes is stopped by the reader's memory limit (upload_read.h).
//
// A point cloud's decoder sizes each attribute from the count of points its
// header claims (up to 2 billion) and the attribute's components (up to 255
// of 8 bytes): refused when that claims more than kDracoCloudBytesPerByte
// bytes (8 a component) a byte of the stream, with 256 MiB always allowed.
// Honest clouds stay far under it: a regular grid of a million points at 14
// bits takes 0.5 to 1.2 bytes a point (draco_encoder's kd-tree and
// sequential methods) for 24 claimed; only degenerate clouds (all points at
// one place, 1-bit positions) go over, and only past 10 million points.
void check_draco_counts(std::string_view bytes, const std::string& name) {
  constexpr std::uint64_t kDracoFacesPerByte = 1024, kAlwaysAllowed = std::uint64_t(1) << 20;
  constexpr std::uint64_t kDracoCloudBytesPerByte = 1024, kCloudAlwaysAllowed = std::uint64_t(256) << 20;
  const std::optional<DracoClaims> c = draco_claims(bytes);
  if (!c) return;
  if (c->point_cloud) {
    if (c->old_kd_tree)
      throw ParseError(name,
                       "a kd-tree Draco point cloud of a bitstream before 2.3 (Draco before 1.3) is not read: "
                       "encode it again with a current draco_encoder",
                       std::nullopt, std::nullopt);
    const std::uint64_t most = std::max<std::uint64_t>(kCloudAlwaysAllowed, kDracoCloudBytesPerByte * bytes.size());
    // Over 2^31 points Draco refuses by itself; the product then cannot overflow.
    const std::uint64_t claimed =
        std::min<std::uint64_t>(c->points, std::uint64_t(1) << 32) * std::max<std::uint64_t>(c->components, 1) * 8;
    if (claimed > most)
      throw ParseError(name,
                       "the Draco header claims " + std::to_string(c->points) + " points of " +
                           std::to_string(c->components) + " components (" + std::to_string(claimed) + " bytes), but " +
                           std::to_string(bytes.size()) + " bytes cannot hold more than " + std::to_string(most) +
                           " (a damaged or crafted file)",
                       std::nullopt, std::nullopt);
    return;
  }
  const std::uint64_t most = std::max<std::uint64_t>(kAlwaysAllowed, kDracoFacesPerByte * bytes.size());
  if (c->faces > most)
    throw ParseError(name,
                     "the Draco header claims " + std::to_string(c->faces) + " faces, but " +
                         std::to_string(bytes.size()) + " bytes cannot hold more than " + std::to_string(most) +
                         " (a damaged or crafted file)",
                     std::nullopt, std::nullopt);
  if (c->vertices > 3 * std::max<std::uint64_t>(c->faces, 1))
    throw ParseError(name,
                     "the Draco header claims " + std::to_string(c->vertices) + " vertices for " +
                         std::to_string(c->faces) + " faces (a damaged or crafted file)",
                     std::nullopt, std::nullopt);
}

void read_draco(std::string_view bytes, const std::string& name, ReadResult& result) {
  if (bytes.empty()) throw ParseError(name, "the file is empty", std::nullopt, std::nullopt);
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) throw ParseError(name, "not a Draco file: " + type.status().error_msg_string(), std::nullopt, 0);
  draco::Decoder decoder;
  auto fail = [&](const draco::Status& s) {
    throw ParseError(name, "Draco could not decode it: " + s.error_msg_string(), std::nullopt, std::nullopt);
  };
  check_draco_counts(bytes, name);
  if (type.value() == draco::POINT_CLOUD) {
    // A scan: its points become a mesh with no faces (core/point_cloud.h).
    auto decoded = decoder.DecodePointCloudFromBuffer(&buffer);
    if (!decoded.ok()) fail(decoded.status());
    from_draco(*decoded.value(), nullptr, name, result);
    return;
  }
  if (type.value() != draco::TRIANGULAR_MESH)
    throw ParseError(name, "the Draco file holds neither a triangle mesh nor a point cloud", std::nullopt, 0);
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) fail(decoded.status());
  from_draco(*decoded.value(), decoded.value().get(), name, result);
}

std::string write_draco(const Mesh& mesh, const WriteOptions& options, std::span<const std::uint32_t> face_material,
                        bool stored_ids) {
  check_float_range(mesh);
  auto dm = to_draco(mesh, face_material, stored_ids);
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.position_bits);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, options.normal_bits);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, options.uv_bits);
  const int speed = std::clamp(options.draco_speed, 0, 10);
  encoder.SetSpeedOptions(speed, speed);
  draco::EncoderBuffer buf;
  // A mesh with no faces is a point cloud, and Draco writes it as one (what
  // draco3d's decoder, and so the viewer, reads as POINT_CLOUD), its points
  // in their order: the kd-tree method would sort them, and the viewer's
  // point i is the stored vertex i (draco_stored_order).
  const bool cloud = mesh.num_faces() == 0;
  if (cloud) encoder.SetEncodingMethod(draco::POINT_CLOUD_SEQUENTIAL_ENCODING);
  const draco::Status s = cloud ? encoder.EncodePointCloudToBuffer(*dm, &buf) : encoder.EncodeMeshToBuffer(*dm, &buf);
  if (!s.ok()) throw Error("Draco could not encode the mesh: " + s.error_msg_string());
  return to_string(buf);
}

std::string write_draco(const Mesh& mesh, const WriteOptions& options) { return write_draco(mesh, options, {}, false); }

std::string write_glb(const Mesh& mesh) {
  auto dm = to_draco(mesh);
  draco::GltfEncoder encoder;
  draco::EncoderBuffer buf;
  const draco::Status s = encoder.EncodeToBuffer(*dm, &buf);
  if (!s.ok()) throw Error("the glTF writer failed: " + s.error_msg_string());
  return to_string(buf);
}

}  // namespace cgview::detail

namespace cgview {

std::string write_draco_with_materials(const Mesh& mesh, std::span<const std::uint32_t> face_material,
                                       const WriteOptions& options) {
  return detail::write_draco(mesh, options, face_material, false);
}

namespace {
std::unique_ptr<draco::Mesh> decode_draco(std::string_view bytes) {
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) throw InvalidInput("Draco could not decode the mesh: " + decoded.status().error_msg_string());
  return std::move(decoded).value();
}
}  // namespace

DracoStoredOrder draco_stored_order(std::string_view bytes, const Mesh& written,
                                    std::span<const std::uint32_t> face_material, const WriteOptions& options) {
  if (written.num_faces() == 0) {
    // A point cloud is written in its order (write_draco): point i is vertex
    // i.  Its header says whether it is that cloud; no need to decode it.
    const std::optional<detail::DracoClaims> c = detail::draco_claims(bytes);
    if (!c || !c->point_cloud || c->points != written.num_vertices())
      throw InvalidInput("the Draco stream does not decode as the point cloud written (" +
                         std::to_string(c ? c->points : 0) + " points against " +
                         std::to_string(written.num_vertices()) + ")");
    DracoStoredOrder order;
    order.points.resize(written.num_vertices());
    std::iota(order.points.begin(), order.points.end(), 0u);
    return order;
  }
  const std::unique_ptr<draco::Mesh> plain = decode_draco(bytes);
  const std::unique_ptr<draco::Mesh> dm = decode_draco(detail::write_draco(written, options, face_material, true));
  // The attribute must not change Draco's traversal: the same points, at the same places, and the same faces.
  const draco::PointAttribute* pa = plain->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  const draco::PointAttribute* pb = dm->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  std::string differs;
  if (!pa || !pb || plain->num_points() != dm->num_points() || plain->num_faces() != dm->num_faces())
    differs = std::to_string(plain->num_points()) + " points and " + std::to_string(plain->num_faces()) +
              " faces against " + std::to_string(dm->num_points()) + " and " + std::to_string(dm->num_faces());
  // Draco may number the points otherwise once there is one more attribute,
  // but the faces come in the same order, each with the same corners (at the
  // same quantized places) in the same turn: that gives the plain stream's
  // point of each point of the other.
  using P = std::array<float, 3>;
  auto at = [](const draco::PointAttribute* a, draco::PointIndex p) {
    P x;
    a->GetMappedValue(p, x.data());
    return x;
  };
  std::vector<std::uint32_t> plain_of(dm->num_points(), ~0u);
  for (draco::FaceIndex f(0); differs.empty() && f < plain->num_faces(); ++f) {
    const auto &fa = plain->face(f), &fb = dm->face(f);
    int turn = -1;
    for (int r = 0; r < 3 && turn < 0; ++r) {
      bool ok = true;
      for (int k = 0; k < 3 && ok; ++k) {
        const std::uint32_t b = fb[(k + r) % 3].value();
        ok = at(pa, fa[k]) == at(pb, fb[(k + r) % 3]) && (plain_of[b] == ~0u || plain_of[b] == fa[k].value());
      }
      if (ok) turn = r;
    }
    if (turn < 0) differs = "face " + std::to_string(f.value());
    else
      for (int k = 0; k < 3; ++k) plain_of[fb[(k + turn) % 3].value()] = fa[k].value();
  }
  // One point for one point: each of the plain stream's points named once.
  std::vector<std::uint32_t> matches(plain->num_points(), 0);
  for (const std::uint32_t a : plain_of)
    if (a != ~0u) ++matches[a];
  for (std::size_t a = 0; differs.empty() && a < matches.size(); ++a)
    if (matches[a] != 1) differs = "point " + std::to_string(a) + " matched " + std::to_string(matches[a]) + " times";
  if (!differs.empty())
    throw InvalidInput("the Draco stream does not decode as the mesh written with its vertex ids does (" + differs +
                       ")");
  const draco::AttributeMetadata* named = dm->GetAttributeMetadataByStringEntry("name", detail::kVertexIdAttribute);
  const draco::PointAttribute* ids = named ? dm->GetAttributeByUniqueId(named->att_unique_id()) : nullptr;
  if (!ids || ids->num_components() != 1) throw Error("Draco lost the vertex ids");
  DracoStoredOrder order;
  order.points.assign(plain->num_points(), 0);
  std::vector<std::uint32_t> stored_of(dm->num_points());  // the ids stream's points' stored vertices
  for (draco::PointIndex p(0); p < dm->num_points(); ++p) {
    ids->GetMappedValue(p, &stored_of[p.value()]);
    order.points[plain_of[p.value()]] = stored_of[p.value()];
  }
  // The written faces by their corners, sorted: a decoded face's corners may
  // come turned.  Equal faces (the same three vertices) are taken in order.
  using Key = std::array<std::uint32_t, 3>;
  auto key = [](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    Key k{a, b, c};
    std::sort(k.begin(), k.end());
    return k;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return (std::size_t(k[0]) * 0x9E3779B97F4A7C15ull) ^ (std::size_t(k[1]) * 0xC2B2AE3D27D4EB4Full) ^
             (std::size_t(k[2]) * 0x165667B19E3779F9ull);
    }
  };
  std::unordered_map<Key, std::uint32_t, Hash> first;  // a key's first face; more in `next`
  std::vector<std::uint32_t> next(written.num_faces(), ~0u);
  first.reserve(written.num_faces());
  for (std::size_t f = written.num_faces(); f-- > 0;) {
    const auto& t = written.faces[f];
    const auto [it, fresh] =
        first.try_emplace(key(std::uint32_t(t[0]), std::uint32_t(t[1]), std::uint32_t(t[2])), std::uint32_t(f));
    if (!fresh) {
      next[f] = it->second;
      it->second = std::uint32_t(f);
    }
  }
  order.faces.resize(dm->num_faces());
  for (draco::FaceIndex f(0); f < dm->num_faces(); ++f) {
    const auto& face = dm->face(f);
    const auto it = first.find(key(stored_of[face[0].value()], stored_of[face[1].value()], stored_of[face[2].value()]));
    if (it == first.end() || it->second == ~0u)
      throw InvalidInput("decoded face " + std::to_string(f.value()) + " is none of the written mesh's faces");
    order.faces[f.value()] = it->second;
    it->second = next[it->second];
  }
  return order;
}

}  // namespace cgview
