// The selection as an algorithm input (a faces parameter) and extract_faces,
// the algorithm that uses it.  The SelectionParam tests go through the
// registry on purpose: the schema, the JSON and the job's range check.
#include "filters/extract_faces.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>

#include "algorithm_json.h"
#include "algorithm_support.h"
#include "invalid_input.h"
#include "registry/registry.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::run_algorithm;

const ParamSpec& faces_spec() {
  for (const ParamSpec& s : find_algorithm("extract_faces").params)
    if (s.name == "faces") return s;
  throw std::runtime_error("no faces parameter");
}

using test::invalid_input_message;

TEST(SelectionParam, DeclaredAsFacesAndShownInTheSchema) {
  EXPECT_EQ(faces_spec().type, ParamType::faces);
  EXPECT_TRUE(std::get<Ids>(faces_spec().default_value).empty());
  const nlohmann::json j = protocol::to_json(find_algorithm("extract_faces"));
  const auto& s = j["params"]["properties"]["faces"];
  EXPECT_EQ(s["type"], "array");
  EXPECT_EQ(s["items"]["type"], "integer");
  EXPECT_EQ(s["x-cgview-selection"], "faces");
  EXPECT_EQ(s["default"], nlohmann::json::array());
}

TEST(SelectionParam, ParsesCommaListsSortedAndUnique) {
  EXPECT_EQ(std::get<Ids>(parse_param(faces_spec(), "3,1, 2\n7 1")), (Ids{1, 2, 3, 7}));
  EXPECT_TRUE(std::get<Ids>(parse_param(faces_spec(), "")).empty());
  EXPECT_EQ(invalid_input_message([] { parse_param(faces_spec(), "1,x,3"); }),
            "parameter 'faces': must be ids separated by commas, got 'x,3'");
  EXPECT_NE(invalid_input_message([] { parse_param(faces_spec(), "-1"); }).find("parameter 'faces'"),
            std::string::npos);
}

TEST(SelectionParam, FromJsonArraysOnly) {
  const Algorithm& a = find_algorithm("extract_faces");
  const auto v = protocol::params_from_json(a, nlohmann::json::parse(R"({"faces": [5, 0, 5]})"));
  EXPECT_EQ(std::get<Ids>(v.at("faces")), (Ids{0, 5}));
  EXPECT_NE(invalid_input_message([&] {
              protocol::params_from_json(a, nlohmann::json::parse(R"({"faces": [1, -2]})"));
            }).find("parameter 'faces': ids must be non-negative integers, got -2"),
            std::string::npos);
  EXPECT_NE(invalid_input_message([&] {
              protocol::params_from_json(a, nlohmann::json::parse(R"({"faces": 3})"));
            }).find("parameter 'faces': must be a list of face ids"),
            std::string::npos);
}

TEST(SelectionParam, IdsOutOfRangeAreRefusedNamingTheId) {
  const Mesh cube = test::box();  // 12 faces, 8 vertices
  EXPECT_EQ(invalid_input_message([&] {
              run_algorithm("extract_faces", cube, {{"faces", Ids{0, 12}}});
            }),
            "parameter 'faces': face id 12 is out of range (the mesh has 12 faces)");
  EXPECT_EQ(invalid_input_message([&] {
              check_selections(find_algorithm("extract_faces").params, {{"faces", Ids{40}}}, 8, 12);
            }),
            "parameter 'faces': face id 40 is out of range (the mesh has 12 faces)");
  EXPECT_EQ(invalid_input_message([&] { run_algorithm("extract_faces", cube, {}); }),
            "parameter 'faces': select at least one face");
}

TEST(ExtractFaces, KeepsExactlyTheSelectedFacesInOrder) {
  const Mesh g = test::grid(4);  // 32 triangles, 25 vertices
  const Ids sel{0, 1, 9, 31};
  const ExtractFacesResult r = extract_faces(g, {.faces = sel});
  const Mesh& out = r.mesh;
  ASSERT_EQ(out.num_faces(), sel.size());
  for (std::size_t k = 0; k < sel.size(); ++k)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(out.positions[out.faces[k][c]], g.positions[g.faces[sel[k]][c]]);
  // Only the vertices used remain.
  std::vector<bool> used(out.num_vertices(), false);
  for (const Tri& t : out.faces)
    for (const Index v : t) used[v] = true;
  EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](bool b) { return b; }));
  double area = 0;
  for (const Index f : sel) area += face_areas(g)[f];
  EXPECT_NEAR(r.metrics.at("area"), area, 1e-12);
  EXPECT_EQ(r.metrics.at("faces"), 4.0);
}

TEST(ExtractFaces, InvertDeletesTheSelection) {
  const Mesh cube = test::box();
  const Mesh out = extract_faces(cube, {.faces = {0, 1}, .invert = true}).mesh;
  EXPECT_EQ(out.num_faces(), 10u);
  for (std::size_t k = 0; k < out.num_faces(); ++k)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(out.positions[out.faces[k][c]], cube.positions[cube.faces[k + 2][c]]);
}

// A direct call has no job to check its ids against the mesh: the function
// does, with the job's message.
TEST(ExtractFaces, DirectCallsRefuseIdsOutOfRangeAndNoSelection) {
  const Mesh cube = test::box();
  EXPECT_EQ(invalid_input_message([&] {
              extract_faces(cube, {.faces = {0, 12}});
            }),
            "parameter 'faces': face id 12 is out of range (the mesh has 12 faces)");
  EXPECT_EQ(invalid_input_message([&] { extract_faces(cube); }), "parameter 'faces': select at least one face");
}

TEST(ExtractFaces, ProgressIsReported) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, [] { return false; });
  extract_faces(test::box(), {.faces = {0}}, &ctx);
  EXPECT_EQ(last, 1.0);
}

TEST(ExtractFaces, RegisteredInTheFiltersArea) { EXPECT_EQ(find_algorithm("extract_faces").info.area, "filters"); }

}  // namespace
}  // namespace cgview
