// Curve skeleton files (io/skeleton_io.h): every format round-trips, files
// of other tools are read, bad files name their line.
#include "io/skeleton_io.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>

#include "core/errors.h"
#include "skeleton/skeleton_measures.h"
#include "skeleton_shapes.h"

namespace cgview {
namespace {

using test::sample_skeleton;

TEST(SkeletonFiles, EveryFormatRoundTrips) {
  const Skeleton s = sample_skeleton();
  for (const char* name : {"y.polylines.txt", "y.cg", "y.obj", "y.json"}) {
    const SkeletonFormat f = skeleton_format_from_name(name);
    const Skeleton back = read_skeleton_bytes(write_skeleton_bytes(s, f), f, name);
    ASSERT_EQ(back.nodes.size(), s.nodes.size()) << name;
    ASSERT_EQ(back.edges.size(), s.edges.size()) << name;
    // Same nodes (polylines may renumber them) and the same edges between them.
    const SkeletonMetrics a = skeleton_shape_metrics(s), b = skeleton_shape_metrics(back);
    EXPECT_EQ(a.endpoints, b.endpoints) << name;
    EXPECT_EQ(a.junctions, b.junctions) << name;
    EXPECT_DOUBLE_EQ(a.length, b.length) << name;
    EXPECT_NEAR(measure_distance(s, back).hausdorff, 0.0, 1e-12) << name;
  }
}

TEST(SkeletonFiles, ReadsWhatOtherToolsWrite) {
  // CGAL's polylines: branches share their end points exactly.
  const Skeleton p =
      read_skeleton_bytes("3 0 0 0 0 1 0 0 2 0\n2 0 1 0 1 1 0\n", SkeletonFormat::polylines, "cgal.polylines.txt");
  EXPECT_EQ(p.nodes.size(), 4u);
  EXPECT_EQ(p.edges.size(), 3u);
  // The .cg curve graph of the contraction tools.
  const Skeleton c =
      read_skeleton_bytes("# D:3 NV:3 NE:2\nv 0 0 0\nv 1 0 0\nv 2 0 0\ne 1 2\ne 2 3\n", SkeletonFormat::cg, "a.cg");
  EXPECT_EQ(c.edges.size(), 2u);
  EXPECT_EQ(c.edges[1][1], 2u);
  // OBJ polylines with negative indices, other records ignored.
  const Skeleton o =
      read_skeleton_bytes("o s\nv 0 0 0\nv 1 0 0\nv 2 0 0\nl 1 2 -1\nvn 0 0 1\n", SkeletonFormat::obj, "a.obj");
  EXPECT_EQ(o.edges.size(), 2u);
}

TEST(SkeletonFiles, AStrayLineFeedInAClassicMacFileEnds) {
  // Lines end with '\r' here, so a '\n' is a blank: reading the rest of a
  // "v" record once stopped on it without moving (tests/fuzz/corpus/skeleton/
  // regression-lf-in-cr-file).
  const Skeleton o = read_skeleton_bytes("v 0 0 1\rv 1 0 0 \n 6\rl 1 2\r", SkeletonFormat::obj, "mac.obj");
  EXPECT_EQ(o.nodes.size(), 2u);
  EXPECT_EQ(o.edges.size(), 1u);
  EXPECT_THROW(read_skeleton_bytes("v 0 0 1\rv 1 0\n0\re 1 2 \n x\r", SkeletonFormat::cg, "mac.cg"), ParseError);
}

TEST(SkeletonFiles, BadFilesNameTheLine) {
  const auto line_of = [](const std::string& bytes, SkeletonFormat f) -> std::optional<std::uint64_t> {
    try {
      read_skeleton_bytes(bytes, f, "bad");
    } catch (const ParseError& e) {
      return e.line();
    }
    return std::nullopt;
  };
  EXPECT_EQ(line_of("# D:3\nv 0 0 0\nv 1 0 0\ne 1 3\n", SkeletonFormat::cg), 4u);     // index out of range
  EXPECT_EQ(line_of("v 0 0 0\nv 1 x 0\n", SkeletonFormat::cg), 2u);                   // not a number
  EXPECT_EQ(line_of("v 0 0 0\nv 1 0 0\ne 1 1\n", SkeletonFormat::cg), 3u);            // a loop edge
  EXPECT_EQ(line_of("v 0 0 0\nf 1 2 3\n", SkeletonFormat::cg), 2u);                   // unknown record
  EXPECT_EQ(line_of("2 0 0 0 1 1 1\n3 0 0 0 1 1\n", SkeletonFormat::polylines), 2u);  // short polyline
  EXPECT_EQ(line_of("v 0 0 0\nl 1 7\n", SkeletonFormat::obj), 2u);
  EXPECT_EQ(line_of("{\"nodes\": [[0, 0, 0]],\n \"edges\": [[0, 1]\n", SkeletonFormat::json), 3u);  // not JSON
  EXPECT_THROW(read_skeleton_bytes("{\"nodes\": [[0, 0, 0]], \"edges\": [[0, 4]]}", SkeletonFormat::json, "j"),
               ParseError);
  EXPECT_THROW(read_skeleton_bytes("", SkeletonFormat::cg, "empty"), ParseError);
  // A number past a double: nlohmann's out_of_range escaped as another
  // exception (tests/fuzz/corpus/skeleton/regression-number-overflow).
  EXPECT_THROW(read_skeleton_bytes("362006e8618", SkeletonFormat::json, "big"), ParseError);
  EXPECT_THROW(read_skeleton_bytes("{\"nodes\": [[0, 0, 1e999]], \"edges\": []}", SkeletonFormat::json, "big"),
               ParseError);
  EXPECT_THROW(skeleton_format_from_name("a.stl"), UnsupportedFormat);
}
}  // namespace
}  // namespace cgview
