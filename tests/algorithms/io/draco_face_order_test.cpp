// Draco renumbers vertices and faces; the viewer colours fields and selects
// on the mesh it streamed through each point's stored vertex id (an
// attribute) and each face's stored index (draco_face_order, sent packed).
// Checked with Draco's own decoder: every decoded point is its stored vertex
// (within the quantization), every decoded face is its stored face (the same
// corners in the same turn), and each stored face is named once.
#include <draco/compression/decode.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/errors.h"
#include "face_order.h"
#include "io/draco_io.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

struct Decoded {
  std::vector<Vec3f> positions;          // per point
  std::vector<std::uint32_t> vertex_id;  // per point
  std::vector<std::array<std::uint32_t, 3>> faces;
};

Decoded decode(const std::string& bytes) {
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  auto r = decoder.DecodeMeshFromBuffer(&buffer);
  EXPECT_TRUE(r.ok()) << r.status().error_msg_string();
  const draco::Mesh& m = *r.value();
  const draco::PointAttribute* pos = m.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  const draco::AttributeMetadata* named = m.GetAttributeMetadataByStringEntry("name", kDracoVertexIdAttribute);
  EXPECT_NE(named, nullptr) << "no vertex_id attribute";
  const draco::PointAttribute* ids = named ? m.GetAttributeByUniqueId(named->att_unique_id()) : nullptr;
  Decoded d;
  for (draco::PointIndex p(0); p < m.num_points(); ++p) {
    float xyz[3];
    pos->GetMappedValue(p, xyz);
    d.positions.push_back({xyz[0], xyz[1], xyz[2]});
    std::uint32_t v = ~0u;
    if (ids) ids->GetMappedValue(p, &v);
    d.vertex_id.push_back(v);
  }
  for (draco::FaceIndex f(0); f < m.num_faces(); ++f)
    d.faces.push_back({m.face(f)[0].value(), m.face(f)[1].value(), m.face(f)[2].value()});
  return d;
}

// A face as its stored corners, turned to start at the smallest (the turn kept).
std::array<std::uint32_t, 3> turned(std::array<std::uint32_t, 3> t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

void expect_stored_order(const Mesh& mesh, std::span<const std::uint32_t> materials, const std::string& what) {
  SCOPED_TRACE(what);
  WriteOptions wo;
  wo.stored_ids = true;
  const std::string bytes = write_draco_with_materials(mesh, materials, wo);
  const Decoded d = decode(bytes);
  const std::vector<std::uint32_t> order = draco_face_order(bytes, mesh);
  ASSERT_EQ(order.size(), mesh.num_faces());
  ASSERT_EQ(d.faces.size(), mesh.num_faces());
  const double tol = bounding_box(mesh).diagonal() / double(1 << 14) * 2;
  for (std::size_t p = 0; p < d.positions.size(); ++p) {
    ASSERT_LT(d.vertex_id[p], mesh.num_vertices());
    const Vec3 s = mesh.positions[d.vertex_id[p]];
    EXPECT_NEAR(d.positions[p].x, s.x, tol);
    EXPECT_NEAR(d.positions[p].y, s.y, tol);
    EXPECT_NEAR(d.positions[p].z, s.z, tol);
  }
  std::vector<int> named(mesh.num_faces(), 0);
  for (std::size_t f = 0; f < d.faces.size(); ++f) {
    ASSERT_LT(order[f], mesh.num_faces());
    ++named[order[f]];
    const auto& t = d.faces[f];
    const auto& s = mesh.faces[order[f]];
    EXPECT_EQ(turned({d.vertex_id[t[0]], d.vertex_id[t[1]], d.vertex_id[t[2]]}),
              turned({std::uint32_t(s[0]), std::uint32_t(s[1]), std::uint32_t(s[2])}))
        << "decoded face " << f;
  }
  EXPECT_TRUE(std::all_of(named.begin(), named.end(), [](int n) { return n == 1; }));
  // The wire form gives the same order back, smaller than the raw indices.
  const std::string packed = protocol::pack_face_order(order);
  EXPECT_EQ(protocol::unpack_face_order(packed, order.size()), order);
  if (mesh.num_faces() > 1000) EXPECT_LT(packed.size(), order.size() * 4 / 2);
}

TEST(DracoFaceOrder, EveryDecodedFaceIsItsStoredFace) {
  expect_stored_order(test::uv_sphere(1.0, 40, 80), {}, "a sphere");
  expect_stored_order(test::torus(), {}, "a torus");
  expect_stored_order(test::merged(test::box(), test::box({3, 0, 0}, {4, 1, 1})), {}, "two boxes");
}

TEST(DracoFaceOrder, MaterialsSplitVerticesThatKeepTheirStoredIds) {
  const Mesh m = test::uv_sphere(1.0, 20, 40);
  std::vector<std::uint32_t> material(m.num_faces());
  for (std::size_t f = 0; f < m.num_faces(); ++f) material[f] = std::uint32_t(f % 3);
  expect_stored_order(m, material, "three materials, every vertex on a boundary");
}

TEST(DracoFaceOrder, PerCornerTextureCoordinatesSplitVerticesThatKeepTheirStoredIds) {
  Mesh m = test::box();
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    m.uv_faces.push_back({Index(3 * f), Index(3 * f + 1), Index(3 * f + 2)});
    for (int k = 0; k < 3; ++k) m.uvs.push_back({float(k) / 2, float(f) / float(m.num_faces())});
  }
  ASSERT_FALSE(m.attributes_per_vertex());
  expect_stored_order(m, {}, "a box with a UV seam at every edge");
}

TEST(DracoFaceOrder, EqualFacesAreEachNamedOnce) {
  Mesh m = test::box();
  m.faces.push_back(m.faces[0]);
  m.faces.push_back(m.faces[0]);
  expect_stored_order(m, {}, "a face three times");
}

TEST(DracoFaceOrder, BytesWithoutIdsAreRefusedSayingSo) {
  const Mesh m = test::box();
  const std::string plain = write_draco_with_materials(m, {});
  try {
    draco_face_order(plain, m);
    FAIL() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("no vertex ids"), std::string::npos) << e.what();
  }
  EXPECT_THROW(protocol::unpack_face_order("not zlib", 12), Error);
}

}  // namespace
}  // namespace cgview
