// Each artifact kind's codec: the stored form read back equals what was
// stored, every export format is read back by the reader that owns the
// format, and the stored file is served as it is.
#include "artifacts/artifact_codec.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "core/animation.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/skeleton_io.h"
#include "open3d_reference.h"
#include "test_support.h"
#include "voxel/voxel_io.h"

namespace cgview {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const OutputKind kKinds[] = {OutputKind::mesh,      OutputKind::scalar_field, OutputKind::voxel_grid,
                             OutputKind::skeleton,  OutputKind::metrics,      OutputKind::text,
                             OutputKind::animation, OutputKind::vector_field, OutputKind::points};

ScalarField sphere_field(const Mesh& m) {
  ScalarField f{"height", Location::vertex, ColorHint::symmetric, {}};
  for (const Vec3& p : m.positions) f.values.push_back(float(p.z));
  return f;
}

// The outward normal of a unit sphere at each vertex, face by face turned
// into a per-vertex field: its own position.
VectorField sphere_normals(const Mesh& m) {
  VectorField f{"outward normal", Location::vertex, VectorHint::arrow, {}};
  for (const Vec3& p : m.positions) f.values.push_back({float(p.x), float(p.y), float(p.z)});
  return f;
}

VoxelGrid ball(int n) {
  VoxelGrid g({n, n, n}, {-1, -1, -1}, 2.0 / n, VoxelType::bit);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if ((i - n / 2) * (i - n / 2) + (j - n / 2) * (j - n / 2) + (k - n / 2) * (k - n / 2) < n * n / 5)
          g.set({i, j, k}, 1);
  return g;
}

Skeleton y_skeleton() {
  Skeleton s;
  s.nodes = {{0, 0, 0}, {0, 0, 1}, {1, 0, 2}, {-1, 0, 2}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}};
  return s;
}

// A sphere's vertices with their outward normals and a colour by height.
PointCloud sphere_cloud(const Mesh& m) {
  PointCloud c;
  for (const Vec3& p : m.positions) {
    c.positions.push_back(p);
    c.normals.push_back({float(p.x), float(p.y), float(p.z)});
    c.colors.push_back({std::uint8_t(127.5 * (p.z + 1)), 40, 200, 255});
  }
  return c;
}

// One artifact of each kind.
std::vector<Artifact> one_of_each(const Mesh& sphere) {
  Animation anim;
  anim.base = sphere;
  std::vector<Vec3f> moved;
  for (const Vec3& p : sphere.positions) moved.push_back({float(p.x), float(p.y), float(p.z + 0.5)});
  anim.frames = {moved};
  return {{"surface", sphere},
          {"height", sphere_field(sphere)},
          {"grid", ball(12)},
          {"skeleton", y_skeleton()},
          {"metrics", Metrics{{"area", 12.5}, {"genus", 0}}},
          {"message", Text{std::string("bytes \x00\xff as they are", 21)}},
          {"animation", anim},
          {"normals", sphere_normals(sphere)},
          {"scan", sphere_cloud(sphere)}};
}

TEST(ArtifactCodec, EveryKindHasOneCodecFoundByItsKindAndItsName) {
  for (OutputKind k : kKinds) {
    const ArtifactCodec& c = artifact_codec(k);
    EXPECT_EQ(c.kind(), k);
    EXPECT_EQ(artifact_codec(to_string(k)), &c);
    ASSERT_FALSE(c.formats().empty()) << to_string(k);
    EXPECT_TRUE(c.formats().front().served) << "the stored form is served: " << to_string(k);
    for (const ArtifactFormat& f : c.formats()) {
      EXPECT_EQ(f.extension.front(), '.') << f.name;
      EXPECT_FALSE(f.content_type.empty()) << f.name;
    }
  }
  EXPECT_EQ(artifact_codec("tensor_field"), nullptr);
  EXPECT_EQ(std::size(kKinds), std::size(kOutputKinds)) << "every kind is checked here";
  // kind_of names each value's kind, in the order one_of_each makes them.
  std::size_t i = 0;
  for (const Artifact& a : one_of_each(test::uv_sphere())) EXPECT_EQ(kind_of(a.value), kKinds[i++]) << a.name;
}

TEST(ArtifactCodec, TheStoredFormReadsBackAsStoredWithItsSizeInTheEntry) {
  const fs::path dir = test::temp_dir("codec-store");
  const Mesh sphere = test::uv_sphere(1.0, 8, 16);
  for (const Artifact& a : one_of_each(sphere)) {
    const ArtifactCodec& c = artifact_codec(kind_of(a.value));
    const json entry = c.store(a, sphere, dir);
    SCOPED_TRACE(entry.dump());
    EXPECT_EQ(entry["name"], a.name);
    EXPECT_EQ(entry["kind"], to_string(c.kind()));
    EXPECT_EQ(entry["file"], a.name + c.formats().front().extension);
    EXPECT_EQ(entry["bytes"].get<std::uintmax_t>(), fs::file_size(dir / entry["file"].get<std::string>()));
    const ArtifactValue back = c.load(dir, entry);
    ASSERT_EQ(back.index(), a.value.index());
    if (const auto* m = std::get_if<Mesh>(&back)) {
      EXPECT_EQ(m->num_faces(), sphere.num_faces());
      EXPECT_EQ(m->num_vertices(), sphere.num_vertices());
    } else if (const auto* f = std::get_if<ScalarField>(&back)) {
      const ScalarField& in = std::get<ScalarField>(a.value);
      EXPECT_EQ(f->values, in.values);
      EXPECT_EQ(f->name, in.name);
      EXPECT_EQ(f->location, in.location);
      EXPECT_EQ(f->hint, in.hint);
      EXPECT_EQ(entry["count"], in.values.size());
    } else if (const auto* g = std::get_if<VoxelGrid>(&back)) {
      const VoxelGrid& in = std::get<VoxelGrid>(a.value);
      EXPECT_EQ(g->dims(), in.dims());
      EXPECT_EQ(g->count_occupied(), in.count_occupied());
    } else if (const auto* s = std::get_if<Skeleton>(&back)) {
      EXPECT_EQ(s->edges, y_skeleton().edges);
      EXPECT_EQ(s->num_nodes(), 4u);
    } else if (const auto* k = std::get_if<Metrics>(&back)) {
      EXPECT_EQ(*k, std::get<Metrics>(a.value));
    } else if (const auto* t = std::get_if<Text>(&back)) {
      EXPECT_EQ(t->bytes, std::get<Text>(a.value).bytes);
    } else if (const auto* v = std::get_if<VectorField>(&back)) {
      const VectorField& in = std::get<VectorField>(a.value);
      EXPECT_EQ(v->values, in.values);
      EXPECT_EQ(v->name, in.name);
      EXPECT_EQ(v->location, in.location);
      EXPECT_EQ(v->hint, in.hint);
      EXPECT_EQ(entry["count"], in.values.size());
      EXPECT_FLOAT_EQ(entry["max_length"].get<float>(), 1.0f);
    } else if (const auto* pc = std::get_if<PointCloud>(&back)) {
      const PointCloud& in = std::get<PointCloud>(a.value);
      ASSERT_EQ(pc->size(), in.size());
      EXPECT_EQ(pc->colors, in.colors);
      ASSERT_EQ(pc->normals.size(), in.size());
      for (std::size_t i = 0; i < in.size(); ++i) {
        EXPECT_NEAR(pc->positions[i].z, in.positions[i].z, 1e-6);  // float, as PLY stores them
        EXPECT_NEAR(pc->normals[i].z, in.normals[i].z, 1e-6);
      }
    } else if (const auto* an = std::get_if<Animation>(&back)) {
      EXPECT_EQ(an->frame_count(), 2u);
      EXPECT_EQ(an->base.num_faces(), sphere.num_faces());
    }
  }
}

// A point cloud's export, read by our reader (no faces, every point) and by
// the format's owner: Draco's draco_decoder for drc, Open3D for ply and xyz.
void expect_cloud_read_back(const ExportedArtifact& e, const std::string& format, const PointCloud& in,
                            const fs::path& dir) {
  const Mesh ours = read_mesh_bytes(e.bytes, format_from_name(format), e.file_name).mesh;
  EXPECT_EQ(ours.num_faces(), 0u);
  EXPECT_EQ(ours.num_vertices(), in.size());
  const fs::path file = dir / e.file_name;
  write_file_bytes(file, e.bytes);
  std::string log;
  if (format == "drc") {
    const fs::path out = dir / "scan_decoded.ply";
    ASSERT_EQ(test::run("draco_decoder -i '" + file.string() + "' -o '" + out.string() + "'", &log), 0) << log;
    const Mesh decoded = read_mesh(out);
    EXPECT_EQ(decoded.num_faces(), 0u);
    EXPECT_EQ(decoded.num_vertices(), in.size());
    EXPECT_EQ(decoded.normals.size(), in.size());
    EXPECT_EQ(decoded.colors.size(), in.size());
    return;
  }
  ASSERT_TRUE(test::have_open3d()) << "/usr/bin/python3 has no open3d (install Debian's python3-open3d)";
  const auto cloud = test::open3d_read(file, format == "xyz" ? "xyzn" : "auto", &log);
  ASSERT_TRUE(cloud) << log;
  ASSERT_EQ((*cloud)["points"].size(), in.size());
  ASSERT_EQ((*cloud)["normals"].size(), in.size());
  EXPECT_NEAR((*cloud)["points"][7][2].get<double>(), in.positions[7].z, 1e-6);
  EXPECT_NEAR((*cloud)["normals"][7][0].get<double>(), in.normals[7].x, 1e-6);
  if (format == "ply") {  // XYZ holds no colours
    ASSERT_EQ((*cloud)["colors"].size(), in.size());
    EXPECT_NEAR((*cloud)["colors"][7][0].get<double>() * 255, in.colors[7].r, 1e-3);
  }
}

// Each served format, read back by the reader of that format.
TEST(ArtifactCodec, EveryServedFormatIsReadBackByItsOwnReader) {
  const fs::path dir = test::temp_dir("codec-export");
  const Mesh sphere = test::uv_sphere(1.0, 8, 16);
  int checked = 0;
  for (const Artifact& a : one_of_each(sphere)) {
    const ArtifactCodec& c = artifact_codec(kind_of(a.value));
    const json entry = c.store(a, sphere, dir);
    const std::string stored = read_file_bytes(dir / entry["file"].get<std::string>(), 1 << 30);
    for (const ArtifactFormat& f : c.formats()) {
      if (!f.served) continue;
      SCOPED_TRACE(std::string(to_string(c.kind())) + " as " + f.name);
      int asked_for_mesh = 0;
      const ExportedArtifact e = c.exported(dir, entry, f.name, [&] {
        ++asked_for_mesh;
        return sphere;
      });
      EXPECT_EQ(e.content_type, f.content_type);
      EXPECT_EQ(e.file_name, a.name + f.extension);
      if (&f == &c.formats().front()) {
        EXPECT_EQ(e.bytes, stored) << "the stored file, as it is";
      }
      EXPECT_EQ(asked_for_mesh, c.needs_mesh(f) ? 1 : 0);
      switch (c.kind()) {
        case OutputKind::mesh:
          EXPECT_EQ(read_mesh_bytes(e.bytes, format_from_name(f.name), e.file_name).mesh.num_faces(),
                    sphere.num_faces());
          break;
        case OutputKind::scalar_field: {
          const std::size_t n = sphere.num_vertices();
          if (f.name == "f32") {
            EXPECT_EQ(e.bytes.size(), n * 4);
          }
          if (f.name == "json") {
            EXPECT_EQ(json::parse(e.bytes)["values"].size(), n);
          }
          if (f.name == "txt") {
            EXPECT_EQ(std::count(e.bytes.begin(), e.bytes.end(), '\n'), long(n));
          }
          if (f.name == "csv") {
            EXPECT_EQ(std::count(e.bytes.begin(), e.bytes.end(), '\n'), long(n + 1));
          }
          if (f.name == "ply") {
            EXPECT_EQ(read_mesh_bytes(e.bytes, MeshFormat::ply, "f.ply").mesh.num_faces(), sphere.num_faces());
          }
          break;
        }
        case OutputKind::voxel_grid: {
          const fs::path p = dir / e.file_name;
          write_file_bytes(p, e.bytes);
          if (f.name == "vtk") {
            EXPECT_EQ(e.bytes.rfind("# vtk DataFile Version 3.0\n", 0), 0u);
          } else {
            const VoxelGrid g = read_voxel_grid(p);
            EXPECT_EQ(g.count_occupied(), ball(12).count_occupied());
          }
          break;
        }
        case OutputKind::skeleton:
          EXPECT_EQ(read_skeleton_bytes(e.bytes, skeleton_format_from_name(e.file_name), e.file_name).edges,
                    y_skeleton().edges);
          break;
        case OutputKind::metrics:
          EXPECT_EQ(json::parse(e.bytes)["area"], 12.5);
          break;
        case OutputKind::text:
          EXPECT_EQ(e.bytes, std::get<Text>(a.value).bytes);
          break;
        case OutputKind::animation:
          EXPECT_EQ(decode_frames(e.bytes).frame_count(), 2u);
          break;
        case OutputKind::vector_field: {
          const std::size_t n = sphere.num_vertices();
          if (f.name == "f32") {
            EXPECT_EQ(e.bytes.size(), n * 12);
          }
          if (f.name == "json") {
            const json j = json::parse(e.bytes);
            EXPECT_EQ(j["values"].size(), n);
            EXPECT_EQ(j["hint"], "arrow");
            EXPECT_EQ(j["values"][3][2].get<float>(), float(sphere.positions[3].z));
          }
          if (f.name == "csv") {
            EXPECT_EQ(std::count(e.bytes.begin(), e.bytes.end(), '\n'), long(n + 1));
          }
          if (f.name == "ply") {
            // A point cloud at the vertices, the vectors its normals.
            const Mesh cloud = read_mesh_bytes(e.bytes, MeshFormat::ply, "v.ply").mesh;
            ASSERT_EQ(cloud.num_vertices(), n);
            EXPECT_EQ(cloud.num_faces(), 0u);
            ASSERT_EQ(cloud.normals.size(), n);
            EXPECT_NEAR(cloud.normals[5].z, sphere.positions[5].z, 1e-6);
            EXPECT_NEAR(cloud.positions[5].x, sphere.positions[5].x, 1e-6);
          }
          if (f.name == "vtk") {
            EXPECT_EQ(e.bytes.rfind("# vtk DataFile Version 3.0\n", 0), 0u);
            EXPECT_NE(e.bytes.find("POINT_DATA " + std::to_string(n) + "\nVECTORS outward_normal float\n"),
                      std::string::npos);
          }
          break;
        }
        case OutputKind::points:
          expect_cloud_read_back(e, f.name, std::get<PointCloud>(a.value), dir);
          break;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 6 + 5 + 6 + 4 + 1 + 2 + 1 + 5 + 3);
}

TEST(ArtifactCodec, AnUnknownFormatIsRefusedNamingTheKnownOnes) {
  try {
    artifact_codec(OutputKind::scalar_field).format_named("obj");
    FAIL() << "no throw";
  } catch (const UnsupportedFormat& e) {
    EXPECT_STREQ(e.what(), "a scalar field is served as f32, json, txt, csv or ply, not 'obj'");
  }
  // .raw is two files: written by `cgview run`, never served.
  EXPECT_THROW(artifact_codec(OutputKind::voxel_grid).format_named("raw"), UnsupportedFormat);
  EXPECT_EQ(artifact_codec(OutputKind::voxel_grid).format_of_path("g.RAW").name, "raw");
  EXPECT_EQ(artifact_codec(OutputKind::skeleton).format_of_path("s.polylines.txt").name, "polylines");
  EXPECT_EQ(artifact_codec(OutputKind::skeleton).format_named("").name, "obj");
  try {
    artifact_codec(OutputKind::metrics).format_of_path("m.csv");
    FAIL() << "no throw";
  } catch (const UnsupportedFormat& e) {
    EXPECT_STREQ(e.what(), "a metrics table cannot be saved as '.csv' (use .json)");
  }
}

TEST(ArtifactCodec, AStoredFieldWhoseSizeIsNotWholeFloatsIsAParseError) {
  const fs::path dir = test::temp_dir("codec-bad-field");
  write_file_bytes(dir / "d.f32", "1234567");
  const json entry = {{"name", "d"}, {"kind", "scalar_field"}, {"file", "d.f32"}};
  EXPECT_THROW(artifact_codec(OutputKind::scalar_field).load(dir, entry), ParseError);
  write_file_bytes(dir / "v.vec.f32", "12345678");  // two floats, not a triple
  EXPECT_THROW(artifact_codec(OutputKind::vector_field)
                   .load(dir, {{"name", "v"}, {"kind", "vector_field"}, {"file", "v.vec.f32"}}),
               ParseError);
}

TEST(ArtifactCodec, AVectorFieldOnAnotherMeshIsNotWrittenOverIt) {
  const Mesh sphere = test::uv_sphere(1.0, 8, 16);
  const Artifact a{"normals", sphere_normals(sphere)};
  const ArtifactCodec& c = artifact_codec(OutputKind::vector_field);
  EXPECT_THROW(c.encode(a.value, a.name, test::box(), c.format_named("ply")), InvalidInput);
}

}  // namespace
}  // namespace cgview
