// The algorithm registry: what centroid_distance declares, the checking and
// parsing of parameter values, a run through the registry, progress and
// cancellation, the JSON Schema of the API, a one-file algorithm, and
// saving artifacts in the formats other tools read.
#include <gtest/gtest.h>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh/IO/PLY.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "algorithm_json.h"
#include "io/mesh_io.h"
#include "invalid_input.h"
#include "registry/artifact_io.h"
#include "registry/registry.h"
#include "test_support.h"

namespace cgview {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const ParamSpec& spec_of(const Algorithm& a, const std::string& name) {
  for (const auto& p : a.params)
    if (p.name == name) return p;
  throw std::out_of_range("no parameter " + name);
}

using test::invalid_input_message;

// A copy: the result is often a temporary.
ScalarField field_of(const AlgorithmResult& r, std::size_t k = 0) {
  EXPECT_GT(r.artifacts.size(), k);
  return std::get<ScalarField>(r.artifacts.at(k).value);
}

AlgorithmResult run(const std::string& algo, const Mesh& mesh, const std::map<std::string, ParamValue>& values = {}) {
  Context ctx;
  return find_algorithm(algo).run(mesh, values, ctx);
}

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// ---------------------------------------------------------------- registry

TEST(Registry, CentroidDistanceIsRegisteredWithItsParams) {
  ASSERT_TRUE(algorithms().contains("centroid_distance"));
  const Algorithm& a = find_algorithm("centroid_distance");
  EXPECT_EQ(a.info.name, "centroid_distance");
  EXPECT_EQ(a.info.area, "examples");
  EXPECT_FALSE(a.info.title.empty());
  EXPECT_FALSE(a.info.description.empty());
  ASSERT_EQ(a.info.outputs.size(), 1u);
  EXPECT_EQ(a.info.outputs[0].first, "distance");
  EXPECT_EQ(a.info.outputs[0].second, OutputKind::scalar_field);

  ASSERT_EQ(a.params.size(), 2u);
  const ParamSpec& normalize = spec_of(a, "normalize");
  EXPECT_EQ(normalize.type, ParamType::boolean);
  EXPECT_EQ(std::get<bool>(normalize.default_value), false);
  EXPECT_EQ(normalize.info.label, "Normalize");
  EXPECT_FALSE(normalize.info.min || normalize.info.max);
  EXPECT_FALSE(normalize.info.help.empty());

  const ParamSpec& exponent = spec_of(a, "exponent");
  EXPECT_EQ(exponent.type, ParamType::number);
  EXPECT_EQ(std::get<double>(exponent.default_value), 1.0);
  EXPECT_EQ(exponent.info.label, "Exponent");
  ASSERT_TRUE(exponent.info.min && exponent.info.max);
  EXPECT_DOUBLE_EQ(*exponent.info.min, 0.1);
  EXPECT_DOUBLE_EQ(*exponent.info.max, 4.0);
}

TEST(Registry, FindUnknownAlgorithmNamesIt) {
  try {
    find_algorithm("no_such_algorithm");
    FAIL() << "no exception";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("'no_such_algorithm'"), std::string::npos) << e.what();
  }
}

TEST(Registry, RegisteringTheSameNameTwiceIsRefused) {
  Algorithm copy = find_algorithm("centroid_distance");
  EXPECT_THROW(register_algorithm(copy), std::logic_error);
  EXPECT_EQ(algorithms().count("centroid_distance"), 1u);
}

TEST(Registry, EveryAlgorithmIsWellFormed) {
  for (const auto& [name, a] : algorithms()) {
    SCOPED_TRACE(name);
    EXPECT_EQ(a.info.name, name);
    EXPECT_FALSE(a.info.title.empty());
    EXPECT_FALSE(a.info.outputs.empty());
    EXPECT_TRUE(a.run);
    for (const auto& p : a.params) {
      SCOPED_TRACE(p.name);
      EXPECT_FALSE(p.info.label.empty());
      // The default itself must pass the parameter's own rules.
      EXPECT_NO_THROW(check_param(p, p.default_value));
      if (p.info.min && p.info.max) {
        EXPECT_LE(*p.info.min, *p.info.max);
      }
    }
  }
}

// ---------------------------------------------------------------- checking values

TEST(CheckParam, AcceptsValuesInRange) {
  const ParamSpec& e = spec_of(find_algorithm("centroid_distance"), "exponent");
  EXPECT_EQ(std::get<double>(check_param(e, 2.5)), 2.5);
  EXPECT_EQ(std::get<double>(check_param(e, 0.1)), 0.1);  // the bounds are inclusive
  EXPECT_EQ(std::get<double>(check_param(e, 4.0)), 4.0);
}

TEST(CheckParam, IntegerGivenForNumberConverts) {
  const ParamSpec& e = spec_of(find_algorithm("centroid_distance"), "exponent");
  const ParamValue v = check_param(e, 3LL);
  ASSERT_TRUE(std::holds_alternative<double>(v));
  EXPECT_EQ(std::get<double>(v), 3.0);
}

TEST(CheckParam, RejectsOutOfRangeNamingParameterAndRule) {
  const ParamSpec& e = spec_of(find_algorithm("centroid_distance"), "exponent");
  EXPECT_EQ(invalid_input_message([&] { check_param(e, 9LL); }), "parameter 'exponent': 9 is over the maximum 4");
  EXPECT_EQ(invalid_input_message([&] { check_param(e, 0.05); }),
            "parameter 'exponent': 0.05 is under the minimum 0.1");
  const std::string nan = invalid_input_message([&] { check_param(e, std::numeric_limits<double>::quiet_NaN()); });
  EXPECT_NE(nan.find("parameter 'exponent'"), std::string::npos) << nan;
  EXPECT_NE(nan.find("finite"), std::string::npos) << nan;
}

TEST(CheckParam, RejectsWrongTypes) {
  const Algorithm& a = find_algorithm("centroid_distance");
  std::string m = invalid_input_message([&] { check_param(spec_of(a, "exponent"), std::string("two")); });
  EXPECT_EQ(m, "parameter 'exponent': must be a number, got two");
  m = invalid_input_message([&] { check_param(spec_of(a, "exponent"), true); });
  EXPECT_NE(m.find("parameter 'exponent': must be a number"), std::string::npos) << m;
  m = invalid_input_message([&] { check_param(spec_of(a, "normalize"), 1LL); });
  EXPECT_NE(m.find("parameter 'normalize': must be true or false"), std::string::npos) << m;
}

TEST(CheckParam, IntegerChoiceAndTextRules) {
  const ParamSpec integer{"rays", ParamType::integer, 25LL, {.label = "Rays", .min = 1, .max = 100}};
  EXPECT_EQ(std::get<long long>(check_param(integer, 50LL)), 50);
  EXPECT_EQ(std::get<long long>(check_param(integer, 7.0)), 7);  // a whole double is an integer
  EXPECT_EQ(invalid_input_message([&] { check_param(integer, 500LL); }),
            "parameter 'rays': 500 is over the maximum 100");
  EXPECT_EQ(invalid_input_message([&] { check_param(integer, 0LL); }), "parameter 'rays': 0 is under the minimum 1");
  EXPECT_EQ(invalid_input_message([&] { check_param(integer, 2.5); }), "parameter 'rays': must be an integer, got 2.5");

  const ParamSpec choice{"method", ParamType::choice, std::string("fast"), {.choices = {"fast", "exact"}}};
  EXPECT_EQ(std::get<std::string>(check_param(choice, std::string("exact"))), "exact");
  EXPECT_EQ(invalid_input_message([&] { check_param(choice, std::string("slow")); }),
            "parameter 'method': 'slow' is not one of fast, exact");

  const ParamSpec text{"label", ParamType::text, std::string(""), {}};
  EXPECT_EQ(std::get<std::string>(check_param(text, std::string("hi"))), "hi");
  EXPECT_NE(invalid_input_message([&] { check_param(text, 3LL); }).find("parameter 'label': must be text"),
            std::string::npos);
}

// ---------------------------------------------------------------- parsing text

TEST(ParseParam, ParsesCommandLineText) {
  const Algorithm& a = find_algorithm("centroid_distance");
  EXPECT_EQ(std::get<double>(parse_param(spec_of(a, "exponent"), "2")), 2.0);
  EXPECT_EQ(std::get<double>(parse_param(spec_of(a, "exponent"), "0.5")), 0.5);
  for (const char* yes : {"true", "1", "yes", "on"})
    EXPECT_TRUE(std::get<bool>(parse_param(spec_of(a, "normalize"), yes)));
  for (const char* no : {"false", "0", "no", "off"})
    EXPECT_FALSE(std::get<bool>(parse_param(spec_of(a, "normalize"), no)));
}

TEST(ParseParam, RejectsBadTextNamingParameter) {
  const Algorithm& a = find_algorithm("centroid_distance");
  EXPECT_EQ(invalid_input_message([&] { parse_param(spec_of(a, "exponent"), "9"); }),
            "parameter 'exponent': 9 is over the maximum 4");
  EXPECT_EQ(invalid_input_message([&] { parse_param(spec_of(a, "exponent"), "2x"); }),
            "parameter 'exponent': must be a number, got '2x'");
  EXPECT_EQ(invalid_input_message([&] { parse_param(spec_of(a, "exponent"), ""); }),
            "parameter 'exponent': must be a number, got ''");
  EXPECT_EQ(invalid_input_message([&] { parse_param(spec_of(a, "normalize"), "maybe"); }),
            "parameter 'normalize': must be true or false, got 'maybe'");
  const ParamSpec integer{"rays", ParamType::integer, 25LL, {.min = 1, .max = 100}};
  EXPECT_EQ(std::get<long long>(parse_param(integer, "42")), 42);
  EXPECT_EQ(invalid_input_message([&] { parse_param(integer, "4.5"); }),
            "parameter 'rays': must be an integer, got '4.5'");
  EXPECT_EQ(invalid_input_message([&] { parse_param(integer, "101"); }),
            "parameter 'rays': 101 is over the maximum 100");
}

TEST(RunParams, UnknownNameIsRejectedListingTheKnownOnes) {
  const std::string m = invalid_input_message([&] { run("centroid_distance", test::box(), {{"exponnent", 2.0}}); });
  EXPECT_NE(m.find("'exponnent'"), std::string::npos) << m;
  EXPECT_NE(m.find("centroid_distance"), std::string::npos) << m;
  EXPECT_NE(m.find("exponent"), std::string::npos) << m;
  EXPECT_NE(m.find("normalize"), std::string::npos) << m;
}

TEST(RunParams, ValuesAreCheckedWhenRun) {
  EXPECT_EQ(invalid_input_message([&] {
              run("centroid_distance", test::box(), {{"exponent", 9LL}});
            }),
            "parameter 'exponent': 9 is over the maximum 4");
  EXPECT_NE(invalid_input_message([&] {
              run("centroid_distance", test::box(), {{"normalize", 2.0}});
            }).find("parameter 'normalize'"),
            std::string::npos);
}

// ---------------------------------------------------------------- running

// centroid_distance's results are tested by its own test
// (tests/algorithms/examples/centroid_distance_test.cpp), calling the
// function; here, what a run through the registry adds: the artifact named
// as the algorithm declares it, and an integer taken for a number.
TEST(Registry, ARunNamesItsArtifactAndTakesAnIntegerForANumber) {
  const AlgorithmResult r = run("centroid_distance", test::uv_sphere(2.0), {{"exponent", 2LL}});
  ASSERT_EQ(r.artifacts.size(), 1u);
  EXPECT_EQ(r.artifacts[0].name, "distance");
  EXPECT_TRUE(r.warnings.empty());
  // An integer exponent, as JSON or a form would send it.
  for (float v : field_of(r).values) EXPECT_NEAR(v, 4.0, 1e-4);
}

// ---------------------------------------------------------------- progress and cancellation

TEST(Context, ProgressFractionsStayInRangeAndEndAtOne) {
  std::vector<double> fractions;
  std::vector<std::string> stages;
  Context ctx(
      [&](double f, std::string_view stage) {
        fractions.push_back(f);
        stages.emplace_back(stage);
      },
      nullptr);
  // Enough vertices for more than one progress report inside the loop.
  Mesh big;
  for (int i = 0; i < 200000; ++i) big.positions.push_back({double(i % 7), double(i % 11), double(i % 13)});
  find_algorithm("centroid_distance").run(big, {}, ctx);
  ASSERT_GE(fractions.size(), 2u);
  for (double f : fractions) {
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
  }
  for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);
  EXPECT_EQ(fractions.back(), 1.0);
  for (const auto& s : stages) EXPECT_FALSE(s.empty());
}

TEST(Context, CancelledRunThrowsCancelled) {
  int asked = 0;
  Context ctx(nullptr, [&] {
    ++asked;
    return true;
  });
  EXPECT_TRUE(ctx.cancelled());
  EXPECT_THROW(ctx.check_cancelled(), Cancelled);
  asked = 0;
  EXPECT_THROW(find_algorithm("centroid_distance").run(test::uv_sphere(), {}, ctx), Cancelled);
  EXPECT_GE(asked, 1);
  // Cancelled is one of CGView's errors, but not the caller's fault.
  EXPECT_TRUE((std::is_base_of_v<Error, Cancelled>));
  EXPECT_FALSE((std::is_base_of_v<InvalidInput, Cancelled>));
}

TEST(Context, DefaultContextNeverCancels) {
  Context ctx;
  EXPECT_FALSE(ctx.cancelled());
  EXPECT_NO_THROW(ctx.check_cancelled());
  EXPECT_NO_THROW(ctx.progress(0.5, "half"));
}

// ---------------------------------------------------------------- JSON

TEST(AlgorithmJson, SchemaOfCentroidDistance) {
  const json j = protocol::to_json(find_algorithm("centroid_distance"));
  EXPECT_EQ(j["name"], "centroid_distance");
  EXPECT_EQ(j["area"], "examples");
  EXPECT_FALSE(j["title"].get<std::string>().empty());
  ASSERT_EQ(j["outputs"].size(), 1u);
  EXPECT_EQ(j["outputs"][0]["name"], "distance");
  EXPECT_EQ(j["outputs"][0]["kind"], "scalar_field");
  EXPECT_EQ(j["inputs"][0]["kind"], "mesh");
  const json& params = j["params"];
  EXPECT_EQ(params["type"], "object");
  EXPECT_EQ(params["additionalProperties"], false);
  const json& e = params["properties"]["exponent"];
  EXPECT_EQ(e["type"], "number");
  EXPECT_EQ(e["title"], "Exponent");
  EXPECT_EQ(e["default"], 1.0);
  EXPECT_EQ(e["minimum"], 0.1);
  EXPECT_EQ(e["maximum"], 4);
  EXPECT_TRUE(e["description"].is_string());
  const json& n = params["properties"]["normalize"];
  EXPECT_EQ(n["type"], "boolean");
  EXPECT_EQ(n["title"], "Normalize");
  EXPECT_EQ(n["default"], false);
  EXPECT_FALSE(n.contains("minimum") || n.contains("maximum"));
}

TEST(AlgorithmJson, ParamsFromJson) {
  const Algorithm& a = find_algorithm("centroid_distance");
  auto v = protocol::params_from_json(a, json::parse(R"({"exponent": 2, "normalize": true})"));
  ASSERT_TRUE(std::holds_alternative<double>(v.at("exponent")));  // the integer 2 became a number
  EXPECT_EQ(std::get<double>(v.at("exponent")), 2.0);
  EXPECT_EQ(std::get<bool>(v.at("normalize")), true);
  EXPECT_TRUE(protocol::params_from_json(a, json()).empty());
  EXPECT_TRUE(protocol::params_from_json(a, json::object()).empty());
}

TEST(AlgorithmJson, ParamsFromJsonRejectsNamingTheParameter) {
  const Algorithm& a = find_algorithm("centroid_distance");
  auto message = [&](const char* text) {
    return invalid_input_message([&] { protocol::params_from_json(a, json::parse(text)); });
  };
  std::string m = message(R"({"exponent": "2"})");
  EXPECT_NE(m.find("parameter 'exponent'"), std::string::npos) << m;
  m = message(R"({"exponent": [2]})");
  EXPECT_NE(m.find("parameter 'exponent'"), std::string::npos) << m;
  m = message(R"({"exponent": null})");
  EXPECT_NE(m.find("parameter 'exponent'"), std::string::npos) << m;
  m = message(R"({"normalize": 1})");
  EXPECT_NE(m.find("parameter 'normalize'"), std::string::npos) << m;
  m = message(R"({"normalize": {"x": 1}})");
  EXPECT_NE(m.find("parameter 'normalize'"), std::string::npos) << m;
  EXPECT_EQ(message(R"({"exponent": 9})"), "parameter 'exponent': 9 is over the maximum 4");
  m = message(R"({"scale": 2})");
  EXPECT_NE(m.find("'scale'"), std::string::npos) << m;
  EXPECT_NE(m.find("normalize, exponent"), std::string::npos) << m;
  m = message("[1, 2]");
  EXPECT_NE(m.find("params"), std::string::npos) << m;
}

// What forms need beside the schema: the declared order (the properties
// come sorted by name), the advanced ones, and when a parameter applies.
TEST(AlgorithmJson, FormsGetTheDeclaredOrderTheAdvancedOnesAndWhenEachApplies) {
  const json chaos = protocol::to_json(find_algorithm("chaos_map"));
  EXPECT_EQ(chaos["params"]["x-cgview-order"], json({"map", "u", "r", "a", "b", "grid", "steps"}));
  EXPECT_EQ(chaos["params"]["properties"]["u"]["x-cgview-when"],
            json({{"param", "map"}, {"in", {"ikeda", "composite"}}}));
  EXPECT_EQ(chaos["params"]["properties"]["r"]["x-cgview-when"], json({{"param", "map"}, {"in", {"logistic"}}}));
  EXPECT_FALSE(chaos["params"]["properties"]["steps"].contains("x-cgview-when"));
  const json skeleton = protocol::to_json(find_algorithm("skeleton_projection"));
  EXPECT_EQ(skeleton["params"]["properties"]["contexts"]["x-cgview-advanced"], true);
  EXPECT_FALSE(skeleton["params"]["properties"]["views"].contains("x-cgview-advanced"));
  const json mcf = protocol::to_json(find_algorithm("skeleton_mcf"));
  EXPECT_EQ(mcf["params"]["properties"]["medially_centered_speed_tradeoff"]["x-cgview-when"]["in"], json({"true"}));

  // A plugin's description read back keeps all three, in its order.
  const Algorithm back = protocol::algorithm_from_json(chaos);
  std::vector<std::string> names;
  for (const ParamSpec& p : back.params) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"map", "u", "r", "a", "b", "grid", "steps"}));
  EXPECT_EQ(back.params[1].info.when.param, "map");
  EXPECT_EQ(back.params[1].info.when.values, (std::vector<std::string>{"ikeda", "composite"}));
  EXPECT_TRUE(protocol::algorithm_from_json(skeleton).params.size() > 0);
  for (const ParamSpec& p : protocol::algorithm_from_json(skeleton).params)
    EXPECT_EQ(p.info.advanced, skeleton["params"]["properties"][p.name].contains("x-cgview-advanced")) << p.name;

  // Every built-in's conditions hold (registration checks them).
  for (const auto& [name, a] : algorithms()) EXPECT_NO_THROW(check_conditions(a.params)) << name;
}

TEST(AlgorithmJson, AConditionOnWhatCannotSayWhenIsRefused) {
  auto spec = [](std::string name, ParamType type, ParamInfo info) {
    return ParamSpec{std::move(name), type, ParamValue(std::string()), std::move(info)};
  };
  const ParamSpec mode = spec("mode", ParamType::choice, {.choices = {"a", "b"}});
  const ParamSpec flag = spec("flag", ParamType::boolean, {});
  const ParamSpec size = spec("size", ParamType::number, {});
  auto message = [&](ParamCondition when) {
    ParamSpec p = spec("p", ParamType::number, {.when = std::move(when)});
    return invalid_input_message([&] { check_conditions({mode, flag, size, p}); });
  };
  ParamSpec fine = spec("p", ParamType::number, {.when = {"mode", {"b"}}});
  EXPECT_NO_THROW(check_conditions({mode, flag, size, fine}));
  fine.info.when = {"flag", {"false"}};
  EXPECT_NO_THROW(check_conditions({mode, flag, size, fine}));
  EXPECT_EQ(message({"nothing", {"b"}}),
            "parameter 'p' applies when 'nothing' is, but there is no such other parameter");
  EXPECT_EQ(message({"p", {"b"}}), "parameter 'p' applies when 'p' is, but there is no such other parameter");
  EXPECT_EQ(message({"size", {"1"}}),
            "parameter 'p' applies when 'size' is, but only a choice or a boolean can say when");
  EXPECT_EQ(message({"mode", {"c"}}), "parameter 'p' applies when 'mode' is 'c', which it cannot be");
  EXPECT_EQ(message({"flag", {"yes"}}), "parameter 'p' applies when 'flag' is 'yes', which it cannot be");
  EXPECT_EQ(message({"mode", {}}), "parameter 'p' applies when 'mode' has one of no values");
  // A plugin's description naming a missing parameter is refused as it is read.
  json d = protocol::to_json(find_algorithm("chaos_map"));
  d["params"]["properties"]["u"]["x-cgview-when"]["param"] = "mapp";
  EXPECT_NE(invalid_input_message([&] { protocol::algorithm_from_json(d); }).find("'mapp'"), std::string::npos);
}

// ---------------------------------------------------------------- a one-file algorithm

TEST(OneFileAlgorithm, RegisteredByItsFileAlone) {
  ASSERT_TRUE(algorithms().contains("test_one_file_coordinate"))
      << "tests/algorithms/registry/one_file_algorithm.cpp should register itself";
  const Algorithm& a = find_algorithm("test_one_file_coordinate");
  EXPECT_EQ(a.info.area, "tests");
  ASSERT_EQ(a.params.size(), 2u);
  EXPECT_EQ(a.params[0].name, "axis");
  EXPECT_EQ(a.params[0].type, ParamType::choice);
  EXPECT_EQ(std::get<std::string>(a.params[0].default_value), "z");
  EXPECT_EQ(a.params[0].info.choices, (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_EQ(a.params[1].name, "scale");
  EXPECT_EQ(a.params[1].type, ParamType::integer);
  EXPECT_EQ(std::get<long long>(a.params[1].default_value), 2);
  EXPECT_EQ(a.params[1].info.label, "Scale");
  EXPECT_EQ(*a.params[1].info.max, 10);

  const json j = protocol::to_json(a);
  EXPECT_EQ(j["params"]["properties"]["axis"]["type"], "string");
  EXPECT_EQ(j["params"]["properties"]["axis"]["enum"], json({"x", "y", "z"}));
  EXPECT_EQ(j["params"]["properties"]["scale"]["type"], "integer");
  EXPECT_EQ(j["params"]["properties"]["scale"]["default"], 2);
}

TEST(OneFileAlgorithm, Runs) {
  const Mesh box = test::box({0, 0, 0}, {1, 2, 3});
  AlgorithmResult r = run("test_one_file_coordinate", box);  // defaults: z, times 2
  ASSERT_EQ(r.artifacts.size(), 2u);
  ASSERT_EQ(r.warnings.size(), 1u);
  const ScalarField z = field_of(r);
  for (std::size_t i = 0; i < box.num_vertices(); ++i) EXPECT_FLOAT_EQ(z.values[i], float(2 * box.positions[i].z));
  EXPECT_EQ(std::get<Metrics>(r.artifacts[1].value).at("vertices"), 8.0);

  r = run("test_one_file_coordinate", box, {{"axis", std::string("y")}, {"scale", 3LL}});
  const ScalarField y = field_of(r);
  for (std::size_t i = 0; i < box.num_vertices(); ++i) EXPECT_FLOAT_EQ(y.values[i], float(3 * box.positions[i].y));

  EXPECT_EQ(invalid_input_message([&] {
              run("test_one_file_coordinate", box, {{"axis", std::string("w")}});
            }),
            "parameter 'axis': 'w' is not one of x, y, z");
  EXPECT_EQ(invalid_input_message([&] {
              run("test_one_file_coordinate", box, {{"scale", 11LL}});
            }),
            "parameter 'scale': 11 is over the maximum 10");
}

// ---------------------------------------------------------------- saving artifacts

// The distance field of centroid_distance on s.
Artifact sphere_field(const Mesh& s) { return run("centroid_distance", s).artifacts.at(0); }

TEST(ArtifactIo, DefaultExtensions) {
  EXPECT_EQ(default_extension({"m", Mesh{}}), ".ply");
  EXPECT_EQ(default_extension({"f", ScalarField{}}), ".txt");
  EXPECT_EQ(default_extension({"g", VoxelGrid{}}), ".nrrd");
  EXPECT_EQ(default_extension({"s", Skeleton{}}), ".obj");
  EXPECT_EQ(default_extension({"k", Metrics{}}), ".json");
  EXPECT_EQ(default_extension({"t", Text{}}), ".txt");
  EXPECT_EQ(default_extension({"a", Animation{}}), ".frames");
}

TEST(ArtifactIo, TextIsWrittenAsItsBytes) {
  const auto dir = test::temp_dir("artifact_text");
  const std::string bytes("a\0\xff\n", 4);
  write_artifact({"message", Text{bytes}}, Mesh{}, dir / "m.bin");
  EXPECT_EQ(read_file_bytes(dir / "m.bin", 100), bytes);
  EXPECT_THROW(write_artifact({"message", Text{bytes}}, Mesh{}, dir / "m.json"), UnsupportedFormat);
  EXPECT_THROW(check_artifact_extension(OutputKind::animation, "a.ply"), UnsupportedFormat);
  EXPECT_NO_THROW(check_artifact_extension(OutputKind::animation, "a.frames"));
}

TEST(ArtifactIo, ScalarFieldAsTxtHasOneValuePerLine) {
  const Mesh s = test::uv_sphere(2.0);
  const Artifact a = sphere_field(s);
  const fs::path p = test::temp_dir("registry-txt") / "d.txt";
  write_artifact(a, s, p);
  const auto l = lines_of(p);
  ASSERT_EQ(l.size(), s.num_vertices());
  for (const auto& line : l) EXPECT_NEAR(std::stod(line), 2.0, 1e-5) << line;
}

TEST(ArtifactIo, ScalarFieldAsCsvHasHeaderAndIndexValueRows) {
  const Mesh s = test::uv_sphere(2.0);
  const fs::path p = test::temp_dir("registry-csv") / "d.CSV";  // extensions in any case
  write_artifact(sphere_field(s), s, p);
  const auto l = lines_of(p);
  ASSERT_EQ(l.size(), s.num_vertices() + 1);
  EXPECT_EQ(l[0], "vertex,centroid_distance");
  for (std::size_t i = 1; i < l.size(); ++i) {
    const auto comma = l[i].find(',');
    ASSERT_NE(comma, std::string::npos) << l[i];
    EXPECT_EQ(std::stoul(l[i].substr(0, comma)), i - 1);
    EXPECT_NEAR(std::stod(l[i].substr(comma + 1)), 2.0, 1e-5);
  }
}

TEST(ArtifactIo, ScalarFieldAsPlyIsTheMeshWithAProperty) {
  const Mesh s = test::uv_sphere(2.0);
  const fs::path p = test::temp_dir("registry-ply") / "d.ply";
  write_artifact(sphere_field(s), s, p);

  // The header declares the field as a float property of the vertices.
  std::ifstream in(p, std::ios::binary);
  std::string header;
  for (std::string l; std::getline(in, l) && l != "end_header";) header += l + "\n";
  EXPECT_NE(header.find("element vertex " + std::to_string(s.num_vertices()) + "\n"), std::string::npos) << header;
  EXPECT_NE(header.find("property float centroid_distance\n"), std::string::npos) << header;
  EXPECT_LT(header.find("property float centroid_distance"), header.find("element face")) << header;

  // Our reader gives the mesh back.
  const Mesh back = read_mesh(p);
  EXPECT_EQ(back.num_vertices(), s.num_vertices());
  EXPECT_EQ(back.num_faces(), s.num_faces());

  // CGAL's reader too, with the values as a vertex property map.
  using K = CGAL::Simple_cartesian<double>;
  CGAL::Surface_mesh<K::Point_3> sm;
  std::ifstream cin(p, std::ios::binary);
  ASSERT_TRUE(CGAL::IO::read_PLY(cin, sm));
  EXPECT_EQ(sm.number_of_vertices(), s.num_vertices());
  EXPECT_EQ(sm.number_of_faces(), s.num_faces());
  auto [values, found] = sm.property_map<CGAL::Surface_mesh<K::Point_3>::Vertex_index, float>("v:centroid_distance");
  ASSERT_TRUE(found);
  for (auto v : sm.vertices()) EXPECT_NEAR(values[v], 2.0, 1e-5);
}

TEST(ArtifactIo, PlyFieldMustMatchTheMesh) {
  const ScalarField wrong{"w", Location::vertex, ColorHint::standard, {1.0f, 2.0f}};
  EXPECT_THROW(write_artifact({"w", wrong}, test::box(), test::temp_dir("registry-ply-bad") / "w.ply"), InvalidInput);
}

TEST(ArtifactIo, MetricsAsJson) {
  const fs::path p = test::temp_dir("registry-json") / "m.json";
  write_artifact({"m", Metrics{{"area", 6.0}, {"volume", 1.5}, {"count", 8}}}, test::box(), p);
  std::ifstream in(p);
  const json j = json::parse(in);
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j.size(), 3u);
  EXPECT_EQ(j["area"], 6.0);
  EXPECT_EQ(j["volume"], 1.5);
  EXPECT_EQ(j["count"], 8);
}

TEST(ArtifactIo, MetricsJsonStaysValidForAnyNameAndValue) {
  const fs::path p = test::temp_dir("registry-json-odd") / "m.json";
  write_artifact({"m", Metrics{{"say \"hi\"\\", 1.0},
                               {"nan", std::numeric_limits<double>::quiet_NaN()},
                               {"inf", std::numeric_limits<double>::infinity()}}},
                 test::box(), p);
  std::ifstream in(p);
  json j;
  ASSERT_NO_THROW(j = json::parse(in));
  EXPECT_EQ(j["say \"hi\"\\"], 1.0);
  EXPECT_TRUE(j["nan"].is_null());  // JSON has no NaN
  EXPECT_TRUE(j["inf"].is_null());
}

TEST(ArtifactIo, UnsupportedExtensionIsUnsupportedFormat) {
  const Mesh s = test::box();
  const fs::path dir = test::temp_dir("registry-unsupported");
  const Artifact field = sphere_field(s);
  for (const char* name : {"d.vtk", "d.json", "d", "d.obj"}) {
    SCOPED_TRACE(name);
    try {
      write_artifact(field, s, dir / name);
      FAIL() << "no exception";
    } catch (const UnsupportedFormat& e) {
      EXPECT_NE(std::string(e.what()).find(".txt"), std::string::npos) << e.what();  // says what would do
    }
    EXPECT_FALSE(fs::exists(dir / name));
  }
  EXPECT_THROW(write_artifact({"m", Metrics{{"a", 1}}}, s, dir / "m.txt"), UnsupportedFormat);
  // The same rules, checked before a run from the declared kind alone.
  EXPECT_NO_THROW(check_artifact_extension(OutputKind::scalar_field, "d.PLY"));
  EXPECT_NO_THROW(check_artifact_extension(OutputKind::mesh, "m.obj"));
  EXPECT_NO_THROW(check_artifact_extension(OutputKind::metrics, "m.json"));
  EXPECT_THROW(check_artifact_extension(OutputKind::scalar_field, "d.vtk"), UnsupportedFormat);
  EXPECT_THROW(check_artifact_extension(OutputKind::mesh, "m.xyz"), UnsupportedFormat);
  EXPECT_THROW(check_artifact_extension(OutputKind::mesh, "m.gltf"), UnsupportedFormat);
  EXPECT_THROW(check_artifact_extension(OutputKind::voxel_grid, "g.json"), UnsupportedFormat);
  EXPECT_THROW(check_artifact_extension(OutputKind::skeleton, "k.ply"), UnsupportedFormat);
  EXPECT_THROW(check_artifact_extension(OutputKind::metrics, "m.csv"), UnsupportedFormat);
  EXPECT_THROW(write_artifact({"k", Skeleton{}}, s, dir / "k.ply"), UnsupportedFormat);
  EXPECT_THROW(write_artifact({"g", VoxelGrid{}}, s, dir / "g.txt"), UnsupportedFormat);
}

}  // namespace
}  // namespace cgview
