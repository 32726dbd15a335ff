// The voxel grid formats (voxel/voxel_io.h), read back by their published
// specifications (parsed here, independently of voxel_io.cpp); bad files;
// the artifact writer's extensions.
#include "voxel/voxel_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "registry/artifact_io.h"
#include "test_support.h"
#include "voxel_samples.h"

namespace cgview {
namespace {

using test::error_of;

VoxelGrid sample_grid(VoxelType t = VoxelType::bit) {
  // A non-cubic grid with a recognisable pattern.
  VoxelGrid g({5, 7, 3}, {0.5, -1.25, 2.0}, 0.25, t);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 5; ++i)
        if ((i + 2 * j + 3 * k) % 4 == 0 || (i == 4 && j == 6 && k == 2))
          g.set({i, j, k}, t == VoxelType::float32 ? 0.5f + i : float(1 + i));
  return g;
}

void expect_same(const VoxelGrid& a, const VoxelGrid& b, bool geometry = true) {
  ASSERT_EQ(a.dims(), b.dims());
  if (geometry) {
    EXPECT_NEAR(a.voxel_size(), b.voxel_size(), 1e-12);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(a.origin()[d], b.origin()[d], 1e-12);
  }
  for (std::size_t n = 0; n < a.size(); ++n) ASSERT_EQ(a.get(a.unlinear(n)), b.get(b.unlinear(n))) << n;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(VoxelFormatsTest, BinvoxBySpecification) {
  const VoxelGrid g = sample_grid();
  const std::filesystem::path path = test::temp_dir("binvox") / "g.binvox";
  write_voxel_grid(g, path);
  const std::string b = slurp(path);
  // Header lines, then (value, count) byte pairs; y fastest, then z, then x.
  std::istringstream in(b);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "#binvox 1");
  int d0, d1, d2;
  double tx, ty, tz, scale;
  std::string key;
  in >> key >> d0 >> d1 >> d2;
  EXPECT_EQ(key, "dim");
  in >> key >> tx >> ty >> tz;
  EXPECT_EQ(key, "translate");
  in >> key >> scale;
  EXPECT_EQ(key, "scale");
  in >> key;
  EXPECT_EQ(key, "data");
  in.get();
  EXPECT_EQ(d0, 7);  // cubic: padded to the largest side
  EXPECT_EQ(d1, 7);
  EXPECT_EQ(d2, 7);
  EXPECT_DOUBLE_EQ(tx, 0.5);
  EXPECT_DOUBLE_EQ(ty, -1.25);
  EXPECT_DOUBLE_EQ(scale, 7 * 0.25);
  std::vector<std::uint8_t> voxels;
  for (;;) {
    const int v = in.get(), c = in.get();
    if (c == EOF) break;
    ASSERT_TRUE(v == 0 || v == 1);
    ASSERT_GE(c, 1);
    voxels.insert(voxels.end(), std::size_t(c), std::uint8_t(v));
  }
  ASSERT_EQ(voxels.size(), 343u);
  for (int x = 0; x < 7; ++x)
    for (int z = 0; z < 7; ++z)
      for (int y = 0; y < 7; ++y)
        EXPECT_EQ(voxels[std::size_t(y + 7 * z + 49 * x)], g.occupied({x, y, z}) ? 1 : 0) << x << y << z;
  const VoxelGrid back = read_voxel_grid(path);
  EXPECT_EQ(back.dims(), (std::array<int, 3>{7, 7, 7}));
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 7; ++y)
      for (int x = 0; x < 5; ++x) EXPECT_EQ(back.occupied({x, y, z}), g.occupied({x, y, z}));
  EXPECT_EQ(back.count_occupied(), g.count_occupied());
}

TEST(VoxelFormatsTest, NrrdBySpecification) {
  for (VoxelType t : {VoxelType::bit, VoxelType::uint8, VoxelType::float32}) {
    const VoxelGrid g = sample_grid(t);
    const std::filesystem::path path = test::temp_dir("nrrd") / "g.nrrd";
    write_voxel_grid(g, path);
    const std::string b = slurp(path);
    ASSERT_EQ(b.compare(0, 8, "NRRD0004"), 0);
    const std::size_t end = b.find("\n\n");
    ASSERT_NE(end, std::string::npos);
    const std::string head = b.substr(0, end + 1);
    EXPECT_NE(head.find(t == VoxelType::float32 ? "\ntype: float\n" : "\ntype: uint8\n"), std::string::npos) << head;
    EXPECT_NE(head.find("\nsizes: 5 7 3\n"), std::string::npos);
    EXPECT_NE(head.find("\nspace directions: (0.25,0,0) (0,0.25,0) (0,0,0.25)\n"), std::string::npos) << head;
    EXPECT_NE(head.find("\nspace origin: (0.625,-1.125,2.125)\n"), std::string::npos) << head;  // voxel 0's centre
    EXPECT_NE(head.find("\nencoding: raw\n"), std::string::npos);
    const std::string data = b.substr(end + 2);
    const std::size_t bpv = t == VoxelType::float32 ? 4 : 1;
    ASSERT_EQ(data.size(), g.size() * bpv);
    for (std::size_t n = 0; n < g.size(); ++n) {
      if (t == VoxelType::float32) {
        float f;
        std::memcpy(&f, data.data() + 4 * n, 4);
        EXPECT_EQ(f, g.floats()[n]);
      } else {
        EXPECT_EQ(std::uint8_t(data[n]), g.bytes()[n]);
      }
    }
    expect_same(g, read_voxel_grid(path));
  }
}

TEST(VoxelFormatsTest, VtiBySpecification) {
  for (VoxelType t : {VoxelType::uint8, VoxelType::float32}) {
    const VoxelGrid g = sample_grid(t);
    const std::filesystem::path path = test::temp_dir("vti") / "g.vti";
    write_voxel_grid(g, path);
    const std::string b = slurp(path);
    EXPECT_NE(b.find("<VTKFile type=\"ImageData\""), std::string::npos);
    EXPECT_NE(b.find("header_type=\"UInt64\""), std::string::npos);
    EXPECT_NE(b.find("WholeExtent=\"0 5 0 7 0 3\""), std::string::npos);  // cells: one per voxel
    EXPECT_NE(b.find("Origin=\"0.5 -1.25 2\""), std::string::npos);
    EXPECT_NE(b.find("Spacing=\"0.25 0.25 0.25\""), std::string::npos);
    EXPECT_NE(b.find(t == VoxelType::float32 ? "type=\"Float32\"" : "type=\"UInt8\""), std::string::npos);
    const std::size_t u = b.find('_', b.find("<AppendedData"));
    std::uint64_t n;
    std::memcpy(&n, b.data() + u + 1, 8);
    const std::size_t bpv = t == VoxelType::float32 ? 4 : 1;
    ASSERT_EQ(n, g.size() * bpv);
    const std::string ours(reinterpret_cast<const char*>(t == VoxelType::float32 ? (const void*)g.floats().data()
                                                                                 : (const void*)g.bytes().data()),
                           n);
    EXPECT_EQ(b.substr(u + 9, n), ours);
    EXPECT_NE(b.find("</VTKFile>", u + 9 + n), std::string::npos);
    expect_same(g, read_voxel_grid(path));
  }
}

TEST(VoxelFormatsTest, MagicaVoxelBySpecification) {
  const VoxelGrid g = sample_grid(VoxelType::uint8);
  const std::filesystem::path path = test::temp_dir("vox") / "g.vox";
  write_voxel_grid(g, path);
  const std::string b = slurp(path);
  auto i32 = [&](std::size_t at) {
    std::int32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
  };
  ASSERT_EQ(b.substr(0, 4), "VOX ");
  EXPECT_EQ(i32(4), 150);
  ASSERT_EQ(b.substr(8, 4), "MAIN");
  EXPECT_EQ(i32(12), 0);
  EXPECT_EQ(std::size_t(i32(16)), b.size() - 20);
  ASSERT_EQ(b.substr(20, 4), "SIZE");
  EXPECT_EQ(i32(24), 12);
  EXPECT_EQ(i32(32), 5);
  EXPECT_EQ(i32(36), 7);
  EXPECT_EQ(i32(40), 3);
  ASSERT_EQ(b.substr(44, 4), "XYZI");
  const int count = i32(56);
  EXPECT_EQ(std::size_t(count), g.count_occupied());
  EXPECT_EQ(i32(48), 4 + 4 * count);
  for (int v = 0; v < count; ++v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(b.data() + 60 + 4 * v);
    EXPECT_EQ(float(p[3]), g.get({p[0], p[1], p[2]}));
  }
  const std::size_t pal = 60 + 4 * std::size_t(count);
  EXPECT_EQ(b.substr(pal, 4), "RGBA");
  EXPECT_EQ(i32(pal + 4), 1024);
  expect_same(g, read_voxel_grid(path), false);  // .vox has no origin or voxel size
  // Over 256 per side: a clear error.
  EXPECT_NE(error_of([] {
              write_voxel_grid(VoxelGrid({300, 2, 2}, {0, 0, 0}, 1), test::temp_dir("vox2") / "x.vox");
            }).find("at most 256"),
            std::string::npos);
}

TEST(VoxelFormatsTest, RawWithJsonSidecar) {
  for (VoxelType t : {VoxelType::bit, VoxelType::float32}) {
    const VoxelGrid g = sample_grid(t);
    const std::filesystem::path path = test::temp_dir("raw") / "g.raw";
    write_voxel_grid(g, path);
    const nlohmann::json j = nlohmann::json::parse(slurp(path.string() + ".json"));
    EXPECT_EQ(j["dims"], nlohmann::json({5, 7, 3}));
    EXPECT_EQ(j["voxel_size"], 0.25);
    EXPECT_EQ(j["origin"], nlohmann::json({0.5, -1.25, 2.0}));
    EXPECT_EQ(j["data_file"], "g.raw");
    EXPECT_EQ(j["type"], t == VoxelType::bit ? "bit" : "float32");
    EXPECT_EQ(slurp(path).size(), g.size() * (t == VoxelType::float32 ? 4 : 1));
    expect_same(g, read_voxel_grid(path));
  }
}

TEST(VoxelFormatsTest, BinvoxHeaderCommentsBlankLinesAndUnknownKeywordsAreSkipped) {
  // As binvox's own viewer reads a header: a comment, blank lines, a keyword of another tool.
  const std::string head =
      "#binvox 1\n# voxelised by a student's script\n\ndim 2 2 2\r\n  \ntranslate 1 2 3\nfoo bar\nscale 4\ndata\n";
  const VoxelGrid g = decode_binvox(head + std::string("\x00\x01\x01\x07", 4));
  EXPECT_EQ(g.dims(), (std::array<int, 3>{2, 2, 2}));
  EXPECT_EQ(g.count_occupied(), 7u);
  EXPECT_FALSE(g.occupied({0, 0, 0}));
  EXPECT_TRUE(g.occupied({1, 1, 1}));
  EXPECT_DOUBLE_EQ(g.origin().z, 3);
  EXPECT_DOUBLE_EQ(g.voxel_size(), 2);
  // A known keyword with bad values is still refused, at its line's first byte.
  const std::string bad = error_of([] { decode_binvox("#binvox 1\n\ndim 2 x 2\ndata\n\x01\x08"); });
  EXPECT_NE(bad.find("a malformed 'dim' line"), std::string::npos) << bad;
  EXPECT_NE(bad.find("byte 11"), std::string::npos) << bad;
}

TEST(VoxelFormatsTest, BadFilesAreParseErrors) {
  EXPECT_THROW(decode_binvox("#binvox 1\ndim 1000 1000 1000\ndata\n\x01\xff"), ParseError);
  EXPECT_THROW(decode_binvox("hello"), ParseError);
  EXPECT_THROW(decode_nrrd("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 100 100 100\nencoding: raw\n\nxx"), ParseError);
  EXPECT_THROW(decode_vox("VOX "), ParseError);
  std::string vox = encode_vox(sample_grid());
  vox[56] = char(0xff);  // XYZI count far beyond the chunk
  EXPECT_THROW(decode_vox(vox), ParseError);
  EXPECT_THROW(decode_vti("<VTKFile type=\"PolyData\">"), ParseError);
  EXPECT_THROW(read_voxel_grid("x.unknown"), UnsupportedFormat);
  // A bit grid's claim is checked too (fuzz_voxel: a 200-byte NRRD of type
  // bit claimed 4 GB of voxels and got them allocated).
  try {
    (void)decode_nrrd(
        "NRRD0004\ntype: uint8\ncgview_type: bit\ndimension: 3\nsizes: 1000 1000 1000\nencoding: raw\n\nxx");
    ADD_FAILURE() << "a claim of 10^9 voxels in 2 bytes was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("the header claims 1000x1000x1000 voxels, more than the file holds"),
              std::string::npos)
        << e.what();
  }
  // Sizes that no integer holds, or not whole (fuzz_voxel found the first:
  // converting 1e100 to an integer is undefined): refused, naming the size.
  for (const std::string size : {"1e100", "nan", "-inf", "2.5", "0"}) {
    try {
      (void)decode_nrrd("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 " + size + " 2\nencoding: raw\n\nxxxxxxxx");
      ADD_FAILURE() << size << " was read";
    } catch (const ParseError& e) {
      const std::string what = e.what();  // nan and -inf are not numbers to the header's reader
      EXPECT_TRUE(what.find("bad grid dimension") != std::string::npos ||
                  what.find("'sizes' needs 3 numbers") != std::string::npos)
          << what;
    }
    const std::string vti = "<VTKFile type=\"ImageData\"><ImageData WholeExtent=\"0 1 0 " + size +
                            " 0 1\" Origin=\"0 0 0\" Spacing=\"1 1 1\"><Piece><PointData><DataArray type=\"UInt8\" "
                            "format=\"ascii\">0 0 0 0 0 0 0 0</DataArray></PointData></Piece></ImageData></VTKFile>";
    EXPECT_THROW(decode_vti(vti), ParseError) << size;
  }
}

TEST(VoxelFormatsTest, ArtifactWriterTakesEveryVoxelExtension) {
  const Artifact a{"grid", sample_grid()};
  const std::filesystem::path dir = test::temp_dir("artifact");
  for (const char* e : {".binvox", ".raw", ".nrrd", ".vti", ".vox", ".vdb", ".vtk"}) {
    EXPECT_NO_THROW(check_artifact_extension(OutputKind::voxel_grid, std::string("g") + e)) << e;
    write_artifact(a, Mesh{}, dir / (std::string("g") + e));
    EXPECT_TRUE(std::filesystem::exists(dir / (std::string("g") + e))) << e;
  }
  EXPECT_THROW(check_artifact_extension(OutputKind::voxel_grid, "g.png"), UnsupportedFormat);
}

}  // namespace
}  // namespace cgview
