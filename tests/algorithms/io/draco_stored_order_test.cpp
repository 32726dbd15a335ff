// Draco renumbers vertices and faces; the viewer colours fields and selects
// on the mesh it streamed through where each point and face of the stream
// came from (draco_stored_order, sent packed).  Checked with Draco's own
// decoder on the stream the viewer gets: every decoded point is at its
// stored vertex (within the quantization), every decoded face is its stored
// face (the same corners in the same turn), and each stored face is named
// once.
#include <draco/compression/decode.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "core/errors.h"
#include "io/draco_io.h"
#include "io/mesh_io.h"
#include "stored_order.h"
#include "test_support.h"

namespace cgview {
namespace {

struct Decoded {
  std::vector<Vec3f> positions;  // per point
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
  Decoded d;
  for (draco::PointIndex p(0); p < m.num_points(); ++p) {
    float xyz[3];
    pos->GetMappedValue(p, xyz);
    d.positions.push_back({xyz[0], xyz[1], xyz[2]});
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
  const std::string bytes = write_draco_with_materials(mesh, materials);  // the stream, as the server sends it
  const Decoded d = decode(bytes);
  const DracoStoredOrder order = draco_stored_order(bytes, mesh, materials);
  ASSERT_EQ(order.points.size(), d.positions.size());
  ASSERT_EQ(order.faces.size(), mesh.num_faces());
  ASSERT_EQ(d.faces.size(), mesh.num_faces());
  const double tol = bounding_box(mesh).diagonal() / double(1 << 14) * 2;
  for (std::size_t p = 0; p < d.positions.size(); ++p) {
    ASSERT_LT(order.points[p], mesh.num_vertices());
    const Vec3 s = mesh.positions[order.points[p]];
    EXPECT_NEAR(d.positions[p].x, s.x, tol);
    EXPECT_NEAR(d.positions[p].y, s.y, tol);
    EXPECT_NEAR(d.positions[p].z, s.z, tol);
  }
  std::vector<int> named(mesh.num_faces(), 0);
  for (std::size_t f = 0; f < d.faces.size(); ++f) {
    ASSERT_LT(order.faces[f], mesh.num_faces());
    ++named[order.faces[f]];
    const auto& t = d.faces[f];
    const auto& s = mesh.faces[order.faces[f]];
    EXPECT_EQ(turned({order.points[t[0]], order.points[t[1]], order.points[t[2]]}),
              turned({std::uint32_t(s[0]), std::uint32_t(s[1]), std::uint32_t(s[2])}))
        << "decoded face " << f;
  }
  EXPECT_TRUE(std::all_of(named.begin(), named.end(), [](int n) { return n == 1; }));
  // The wire form gives the same order back, smaller than the raw indices.
  const std::string packed = protocol::pack_stored_order(order.points, order.faces);
  const protocol::StoredOrder back = protocol::unpack_stored_order(packed);
  EXPECT_EQ(back.points, order.points);
  EXPECT_EQ(back.faces, order.faces);
  if (mesh.num_faces() > 1000) {
    EXPECT_LT(packed.size(), (order.points.size() + order.faces.size()) * 4 / 2);
  }
}

TEST(DracoStoredOrder, EveryDecodedPointAndFaceIsItsStoredOne) {
  expect_stored_order(test::uv_sphere(1.0, 40, 80), {}, "a sphere");
  expect_stored_order(test::torus(), {}, "a torus");
  expect_stored_order(test::merged(test::box(), test::box({3, 0, 0}, {4, 1, 1})), {}, "two boxes");
}

TEST(DracoStoredOrder, MaterialsSplitVerticesThatKeepTheirStoredIds) {
  const Mesh m = test::uv_sphere(1.0, 20, 40);
  std::vector<std::uint32_t> material(m.num_faces());
  for (std::size_t f = 0; f < m.num_faces(); ++f) material[f] = std::uint32_t(f % 3);
  expect_stored_order(m, material, "three materials, every vertex on a boundary");
}

TEST(DracoStoredOrder, PerCornerTextureCoordinatesSplitVerticesThatKeepTheirStoredIds) {
  Mesh m = test::box();
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    m.uv_faces.push_back({Index(3 * f), Index(3 * f + 1), Index(3 * f + 2)});
    for (int k = 0; k < 3; ++k) m.uvs.push_back({float(k) / 2, float(f) / float(m.num_faces())});
  }
  ASSERT_FALSE(m.attributes_per_vertex());
  expect_stored_order(m, {}, "a box with a UV seam at every edge");
}

TEST(DracoStoredOrder, EqualFacesAreEachNamedOnce) {
  Mesh m = test::box();
  m.faces.push_back(m.faces[0]);
  m.faces.push_back(m.faces[0]);
  expect_stored_order(m, {}, "a face three times");
}

TEST(DracoStoredOrder, AStreamOfAnotherMeshIsRefusedSayingSo) {
  const Mesh box = test::box();
  const std::string other = write_draco_with_materials(test::torus(), {});
  try {
    draco_stored_order(other, box, {});
    FAIL() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("does not decode as"), std::string::npos) << e.what();
  }
  EXPECT_THROW(protocol::unpack_stored_order("not zlib"), Error);
  EXPECT_THROW(protocol::unpack_stored_order(protocol::pack_stored_order({}, {}).substr(0, 4)), Error);
}

}  // namespace
}  // namespace cgview
