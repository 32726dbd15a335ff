// compare_output: results against analytic references (a ramp and its
// shifts and scalings, a sphere and its scaling, a segment and its shift,
// metrics tables), and every way a spec is refused.
#include "compare/compare_output.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "invalid_input.h"
#include "test_support.h"

namespace cgview {
namespace {

using nlohmann::json;
using test::invalid_input_message;

// 0, 1, ..., 100 per vertex: range 100.
ScalarField ramp(double scale = 1, double offset = 0, std::size_t n = 101) {
  ScalarField f{"f", Location::vertex, ColorHint::standard, {}};
  for (std::size_t i = 0; i < n; ++i) f.values.push_back(float(scale * double(i) + offset));
  return f;
}

CompareSpec spec(OutputKind kind, json j = json::object()) { return compare_spec_from_json(j, kind); }

TEST(CompareFields, IdenticalFieldsPassWithNoError) {
  const Verdict v = compare_output(ramp(), ramp(), spec(OutputKind::scalar_field));
  EXPECT_TRUE(v.pass) << v.reason;
  EXPECT_EQ(v.measures.at("mean_error"), 0);
  EXPECT_EQ(v.measures.at("max_error"), 0);
  EXPECT_EQ(v.measures.at("scale"), 100);
  EXPECT_EQ(v.reason, "within tolerance: mean error 0% of the range (3% allowed)");
}

TEST(CompareFields, AnOffsetOfFivePercentFailsAtThreeAndPassesAtTen) {
  const Verdict tight = compare_output(ramp(1, 5), ramp(), spec(OutputKind::scalar_field));
  EXPECT_FALSE(tight.pass);
  EXPECT_NEAR(tight.measures.at("mean_error"), 0.05, 1e-9);
  EXPECT_EQ(tight.reason, "mean error 5% of the range over the 3% allowed");
  const Verdict loose = compare_output(ramp(1, 5), ramp(), spec(OutputKind::scalar_field, {{"tolerance", 0.1}}));
  EXPECT_TRUE(loose.pass) << loose.reason;
  EXPECT_NEAR(loose.measures.at("mean_error"), 0.05, 1e-9);
  EXPECT_NEAR(loose.measures.at("max_error"), 0.05, 1e-9);
  EXPECT_EQ(loose.reason, "within tolerance: mean error 5% of the range (10% allowed)");
}

TEST(CompareFields, NumbersThatWouldReadTheSameGetMoreDigits) {
  // A mean error of 3.0004% against 3% allowed: never "3% over the 3% allowed".
  const Verdict v = compare_output(ramp(1, 3.0004), ramp(), spec(OutputKind::scalar_field));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason, "mean error 3.0004% of the range over the 3% allowed");
}

TEST(CompareFields, AFieldScaledByTwoPassesCorrelationAndFailsRelative) {
  const Verdict c = compare_output(ramp(2), ramp(), spec(OutputKind::scalar_field, {{"method", "correlation"}}));
  EXPECT_TRUE(c.pass) << c.reason;
  EXPECT_NEAR(c.measures.at("correlation"), 1.0, 1e-12);
  EXPECT_EQ(c.reason, "within tolerance: correlation 1 (0.95 required)");
  const Verdict r = compare_output(ramp(2), ramp(), spec(OutputKind::scalar_field));
  EXPECT_FALSE(r.pass);
  EXPECT_NEAR(r.measures.at("mean_error"), 0.5, 1e-9);  // mean of i / 100 over 0..100
  EXPECT_NEAR(r.measures.at("max_error"), 1.0, 1e-9);
}

TEST(CompareFields, AnAntiCorrelatedFieldFailsCorrelation) {
  const Verdict v = compare_output(ramp(-1), ramp(), spec(OutputKind::scalar_field, {{"method", "correlation"}}));
  EXPECT_FALSE(v.pass);
  EXPECT_NEAR(v.measures.at("correlation"), -1.0, 1e-12);
  EXPECT_EQ(v.reason, "correlation -1 under the 0.95 required");
}

TEST(CompareFields, AConstantFieldHasNoCorrelation) {
  const CompareSpec corr = spec(OutputKind::scalar_field, {{"method", "correlation"}});
  const Verdict v = compare_output(ramp(0, 7), ramp(), corr);
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason, "a constant field where the reference varies: no correlation to measure");
  EXPECT_FALSE(compare_output(ramp(), ramp(0, 7), corr).pass);
  EXPECT_TRUE(compare_output(ramp(0, 3), ramp(0, 7), corr).pass);
}

TEST(CompareFields, AConstantReferenceIsScaledByItsMagnitude) {
  // Reference 200 everywhere, result 202: 1% of 200.
  const Verdict v = compare_output(ramp(0, 202), ramp(0, 200), spec(OutputKind::scalar_field));
  EXPECT_TRUE(v.pass) << v.reason;
  EXPECT_NEAR(v.measures.at("mean_error"), 0.01, 1e-9);
  EXPECT_EQ(v.measures.at("scale"), 200);
}

TEST(CompareFields, ValuesThatAreNotNumbersFail) {
  ScalarField r = ramp();
  r.values[3] = std::numeric_limits<float>::quiet_NaN();
  r.values[50] = std::numeric_limits<float>::infinity();
  const Verdict v = compare_output(r, ramp(), spec(OutputKind::scalar_field, {{"tolerance", 1.0}}));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason, "2 of 101 values are not numbers");
}

TEST(CompareFields, WhereTheReferenceIsNotANumberNothingIsCompared) {
  ScalarField s = ramp(), r = ramp(1, 1);
  s.values[10] = std::numeric_limits<float>::infinity();
  r.values[10] = std::numeric_limits<float>::quiet_NaN();
  const Verdict v = compare_output(r, s, spec(OutputKind::scalar_field));
  EXPECT_TRUE(v.pass) << v.reason;
  EXPECT_NEAR(v.measures.at("mean_error"), 0.01, 1e-9);
  s.values.assign(s.values.size(), std::numeric_limits<float>::quiet_NaN());
  EXPECT_NE(
      invalid_input_message([&] { compare_output(r, s, spec(OutputKind::scalar_field)); }).find("no finite value"),
      std::string::npos);
}

TEST(CompareFields, ASizeOrPlaceMismatchFails) {
  const Verdict v = compare_output(ramp(1, 0, 10), ramp(1, 0, 12), spec(OutputKind::scalar_field));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason, "a field of 10 values where the reference has 12");
  ScalarField per_face = ramp();
  per_face.location = Location::face;
  const Verdict w = compare_output(per_face, ramp(), spec(OutputKind::scalar_field));
  EXPECT_FALSE(w.pass);
  EXPECT_EQ(w.reason, "a per-face field where a per-vertex field was expected");
}

TEST(CompareOutput, AnotherKindFails) {
  const Verdict v =
      compare_output(test::box(), Skeleton{{{0, 0, 0}, {1, 0, 0}}, {{0, 1}}, {}, {}}, spec(OutputKind::skeleton));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason, "a mesh where a skeleton was expected");
  EXPECT_EQ(compare_output(Metrics{}, ramp(), spec(OutputKind::scalar_field)).reason,
            "a metrics table where a scalar field was expected");
}

TEST(CompareOutput, ASpecForAnotherKindIsRefused) {
  EXPECT_NE(invalid_input_message([] {
              compare_output(ramp(), ramp(), spec(OutputKind::mesh));
            }).find("method 'hausdorff' is not one for a scalar field (relative, correlation)"),
            std::string::npos);
  EXPECT_NE(invalid_input_message([] { compare_output(ramp(), ramp(), CompareSpec{}); }).find("method ''"),
            std::string::npos);
}

Mesh scaled(Mesh m, double k) {
  for (Vec3& p : m.positions) p = p * k;
  return m;
}

TEST(CompareMeshes, ASphereScaledByTwoPercentIsTwoHundredthsOfTheRadiusAway) {
  // The UV sphere's vertices reach +-1 on every axis: a diagonal of 2 sqrt(3).
  // Its 2% larger copy is homothetic: farthest at the vertices, 0.02 away.
  const Mesh sphere = test::uv_sphere(1.0, 16, 32);
  const double expected = 0.02 / (2 * std::sqrt(3.0));
  const Verdict v = compare_output(scaled(sphere, 1.02), sphere, spec(OutputKind::mesh));
  EXPECT_TRUE(v.pass) << v.reason;  // 0.58% of the diagonal, 1% allowed
  EXPECT_NEAR(v.measures.at("diagonal"), 2 * std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(v.measures.at("hausdorff"), expected, 0.03 * expected);
  EXPECT_EQ(v.reason, "within tolerance: Hausdorff distance 0.577% of the diagonal (1% allowed)");
  const Verdict tight = compare_output(scaled(sphere, 1.02), sphere, spec(OutputKind::mesh, {{"tolerance", 0.005}}));
  EXPECT_FALSE(tight.pass);
  EXPECT_EQ(tight.reason, "Hausdorff distance 0.577% of the diagonal over the 0.5% allowed");
}

TEST(CompareMeshes, IdenticalMeshesAreNoDistanceApartOnEveryCall) {
  const Mesh sphere = test::uv_sphere(1.0, 16, 32);
  const Verdict v = compare_output(sphere, sphere, spec(OutputKind::mesh));
  EXPECT_TRUE(v.pass);
  EXPECT_LT(v.measures.at("hausdorff"), 1e-9);
  // Sampled on a grid, not at random: the same numbers each time.
  const Mesh torus = test::torus();
  const Verdict a = compare_output(torus, scaled(torus, 1.01), spec(OutputKind::mesh));
  const Verdict b = compare_output(torus, scaled(torus, 1.01), spec(OutputKind::mesh));
  EXPECT_EQ(a.measures.at("hausdorff"), b.measures.at("hausdorff"));
  EXPECT_GT(a.measures.at("hausdorff"), 0);
}

// m with the vertices of equal positions made one.
Mesh welded(Mesh m) {
  std::map<std::array<double, 3>, Index> first;
  for (Tri& f : m.faces)
    for (Index& v : f) v = first.try_emplace({m.positions[v].x, m.positions[v].y, m.positions[v].z}, v).first->second;
  return m;
}

TEST(CompareMeshes, AMissingPartOfANonManifoldReferenceCounts) {
  // The reference is two unit boxes welded along an edge, which four faces
  // share (no halfedge structure holds it, yet it is measured whole); the
  // result lacks the second box, whose far corners are sqrt(2) from the
  // first; the reference's box is 2 x 2 x 1.
  const Mesh one = test::box(), two = welded(test::merged(one, test::box({1, 1, 0}, {2, 2, 1})));
  const Verdict v = compare_output(one, two, spec(OutputKind::mesh));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.measures.at("diagonal"), 3);
  EXPECT_NEAR(v.measures.at("hausdorff"), std::sqrt(2.0) / 3, 1e-9);
  // The same boxes unwelded fit a halfedge structure: no distance from the welded ones.
  const Mesh apart = test::merged(one, test::box({1, 1, 0}, {2, 2, 1}));
  EXPECT_LT(compare_output(two, apart, spec(OutputKind::mesh)).measures.at("hausdorff"), 1e-9);
  EXPECT_LT(compare_output(apart, two, spec(OutputKind::mesh)).measures.at("hausdorff"), 1e-9);
  const Verdict w = compare_output(two, one, spec(OutputKind::mesh));
  EXPECT_NEAR(w.measures.at("hausdorff"), std::sqrt(2.0) / std::sqrt(3.0), 1e-9);
}

TEST(CompareMeshes, AnEmptyResultFailsAndAnEmptyReferenceIsRefused) {
  const Verdict v = compare_output(Mesh{}, test::box(), spec(OutputKind::mesh));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason, "a mesh with no faces");
  EXPECT_NE(invalid_input_message([] {
              compare_output(test::box(), Mesh{}, spec(OutputKind::mesh));
            }).find("the reference mesh has no faces"),
            std::string::npos);
}

Skeleton segment(Vec3 a, Vec3 b) { return Skeleton{{a, b}, {{0, 1}}, {}, {}}; }

TEST(CompareSkeletons, ASegmentShiftedByAFractionOfItsLength) {
  // The reference runs 0..1 along x (diagonal 1); the result 0.05 above it.
  const Skeleton reference = segment({0, 0, 0}, {1, 0, 0}), shifted = segment({0, 0.05, 0}, {1, 0.05, 0});
  const Verdict v = compare_output(shifted, reference, spec(OutputKind::skeleton));
  EXPECT_FALSE(v.pass);
  EXPECT_NEAR(v.measures.at("hausdorff"), 0.05, 1e-9);
  EXPECT_NEAR(v.measures.at("mean"), 0.05, 1e-9);
  EXPECT_EQ(v.measures.at("diagonal"), 1);
  EXPECT_EQ(v.reason, "Hausdorff distance 5% of the diagonal over the 1% allowed");
  EXPECT_TRUE(compare_output(shifted, reference, spec(OutputKind::skeleton, {{"tolerance", 0.06}})).pass);
  const Verdict same = compare_output(reference, reference, spec(OutputKind::skeleton));
  EXPECT_TRUE(same.pass);
  EXPECT_EQ(same.measures.at("hausdorff"), 0);
}

TEST(CompareSkeletons, AnInvalidResultFails) {
  const Skeleton bad{{{0, 0, 0}}, {{0, 3}}, {}, {}};
  const Verdict v = compare_output(bad, segment({0, 0, 0}, {1, 0, 0}), spec(OutputKind::skeleton));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason.rfind("an invalid skeleton: ", 0), 0u) << v.reason;
}

TEST(CompareMetrics, PerKeyTolerancesAndAMissingKey) {
  const Metrics reference{{"area", 10}, {"genus", 0}, {"volume", 2}};
  const Metrics result{{"area", 10.05}, {"volume", 2.5}, {"extra", 1}};
  // Only area, 0.5% off: passes at 1%, fails at 0.1%.
  const Verdict loose = compare_output(result, reference, spec(OutputKind::metrics, {{"keys", {{"area", 0.01}}}}));
  EXPECT_TRUE(loose.pass) << loose.reason;
  EXPECT_NEAR(loose.measures.at("area"), 0.005, 1e-12);
  EXPECT_EQ(loose.measures.count("volume"), 0u);
  EXPECT_EQ(loose.reason, "within tolerance: 1 metric");
  const Verdict tight = compare_output(result, reference, spec(OutputKind::metrics, {{"keys", {{"area", 0.001}}}}));
  EXPECT_FALSE(tight.pass);
  EXPECT_EQ(tight.reason, "metric 'area' is 10.05 where the reference has 10 (0.1% allowed)");
  // Every key of the reference at the default 1%: genus is missing, volume 25% off.
  const Verdict all = compare_output(result, reference, spec(OutputKind::metrics));
  EXPECT_FALSE(all.pass);
  EXPECT_EQ(all.reason, "missing metric 'genus'; metric 'volume' is 2.5 where the reference has 2 (1% allowed)");
  EXPECT_NEAR(all.measures.at("volume"), 0.25, 1e-12);
  // A zero reference value allows only (almost) zero.
  EXPECT_TRUE(compare_output(Metrics{{"genus", 0}}, Metrics{{"genus", 0}}, spec(OutputKind::metrics)).pass);
  EXPECT_FALSE(compare_output(Metrics{{"genus", 1}}, Metrics{{"genus", 0}}, spec(OutputKind::metrics)).pass);
  // A key the reference lacks is the teacher's mistake.
  EXPECT_NE(invalid_input_message([&] {
              compare_output(result, reference, spec(OutputKind::metrics, {{"keys", {{"length", 0.1}}}}));
            }).find("metric 'length' is not in the reference"),
            std::string::npos);
}

TEST(CompareSpecJson, DefaultsAreFilledPerKind) {
  const CompareSpec field = spec(OutputKind::scalar_field, nullptr);
  EXPECT_EQ(field.method, "relative");
  EXPECT_EQ(field.tolerance, 0.03);
  EXPECT_EQ(spec(OutputKind::scalar_field, {{"method", "correlation"}}).tolerance, 0.95);
  EXPECT_EQ(spec(OutputKind::mesh).method, "hausdorff");
  EXPECT_EQ(spec(OutputKind::mesh).tolerance, 0.01);
  EXPECT_EQ(spec(OutputKind::skeleton).tolerance, 0.01);
  EXPECT_EQ(spec(OutputKind::metrics).method, "tolerance");
  EXPECT_EQ(spec(OutputKind::metrics).tolerance, 0.01);
  EXPECT_EQ(spec(OutputKind::scalar_field, {{"method", "correlation"}, {"tolerance", -0.5}}).tolerance, -0.5);
  const CompareSpec m = spec(OutputKind::metrics, {{"tolerance", 0.2}, {"keys", {{"area", 0.05}}}});
  EXPECT_EQ(to_json(m), json({{"method", "tolerance"}, {"tolerance", 0.2}, {"keys", {{"area", 0.05}}}}));
  const CompareSpec back = compare_spec_from_json(to_json(m), OutputKind::metrics);
  EXPECT_EQ(back.method, m.method);
  EXPECT_EQ(back.tolerance, m.tolerance);
  EXPECT_EQ(back.keys, m.keys);
  EXPECT_EQ(to_json(field), json({{"method", "relative"}, {"tolerance", 0.03}}));
}

TEST(CompareSpecJson, BadSpecsAreRefusedNamingWhatIsWrong) {
  const auto message = [](json j, OutputKind kind) {
    return invalid_input_message([&] { compare_spec_from_json(j, kind); });
  };
  EXPECT_EQ(message({{"method", "chamfer"}}, OutputKind::mesh),
            "compare spec: method 'chamfer' is not one for a mesh (hausdorff)");
  EXPECT_EQ(message({{"method", "hausdorff"}}, OutputKind::scalar_field),
            "compare spec: method 'hausdorff' is not one for a scalar field (relative, correlation)");
  EXPECT_NE(message({{"tolerance", -0.1}}, OutputKind::mesh).find("is negative"), std::string::npos);
  EXPECT_NE(message({{"method", "correlation"}, {"tolerance", 1.5}}, OutputKind::scalar_field)
                .find("a correlation tolerance is between -1 and 1"),
            std::string::npos);
  EXPECT_EQ(message({{"keys", {{"area", 0.1}}}}, OutputKind::mesh),
            "compare spec: keys are for a metrics table, not a mesh");
  EXPECT_EQ(message({{"keys", {{"area", -1}}}}, OutputKind::metrics),
            "compare spec: key 'area' has a negative tolerance");
  EXPECT_EQ(message({{"keys", {{"area", "1%"}}}}, OutputKind::metrics),
            "compare spec: the tolerance of key 'area' is a number");
  EXPECT_EQ(message({{"tolerence", 0.1}}, OutputKind::mesh),
            "compare spec: unknown field 'tolerence' (method, tolerance, keys)");
  EXPECT_EQ(message({{"tolerance", "5%"}}, OutputKind::mesh), "compare spec: tolerance is a number");
  EXPECT_EQ(message(json::array(), OutputKind::mesh), "compare spec: an object {method, tolerance, keys}");
  for (OutputKind kind : {OutputKind::voxel_grid, OutputKind::text, OutputKind::animation, OutputKind::vector_field})
    EXPECT_NE(message(json::object(), kind).find("cannot be compared"), std::string::npos) << to_string(kind);
  EXPECT_NE(message(json::object(), OutputKind::voxel_grid).find("a voxel grid"), std::string::npos);
}

}  // namespace
}  // namespace cgview
