#include "points/estimate_normals.h"

#include <CGAL/jet_estimate_normals.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/pca_estimate_normals.h>
#include <CGAL/property_map.h>

#include <cmath>
#include <tuple>

#include "core/surface_mesh.h"

namespace cgview {
namespace {

// The point's index rides along: mst_orient_normals reorders the range.
using Row = std::tuple<Point3, Kernel::Vector_3, std::size_t>;

}  // namespace

EstimateNormalsResult estimate_normals(const PointCloud& cloud, const EstimateNormalsParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  cloud.validate();
  const bool jet = p.method == NormalMethod::jet;
  // A quadric has 6 coefficients, a plane 3.
  const std::size_t least = jet ? 6 : 3;
  if (cloud.size() < least)
    throw InvalidInput(std::string("estimate_normals: the ") + (jet ? "jet" : "pca") + " method needs at least " +
                       std::to_string(least) + " points; the cloud has " + std::to_string(cloud.size()));
  ctx.progress(0.0, "normals");

  std::vector<Row> rows;
  rows.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& q = cloud.positions[i];
    rows.emplace_back(Point3(q.x, q.y, q.z), Kernel::Vector_3(0, 0, 0), i);
  }
  const auto params = CGAL::parameters::point_map(CGAL::Nth_of_tuple_property_map<0, Row>())
                          .normal_map(CGAL::Nth_of_tuple_property_map<1, Row>());
  // No `callback` parameter for progress: CGAL 5.5's jet and pca keep a
  // reference to a temporary copy of it (choose_parameter over the value
  // get_parameter returns), which crashed here; the fit is checked for
  // cancellation after it, the orientation before it.
  const unsigned k = unsigned(p.neighbors);
  if (jet) CGAL::jet_estimate_normals<CGAL::Sequential_tag>(rows, k, params);
  else CGAL::pca_estimate_normals<CGAL::Sequential_tag>(rows, k, params);
  ctx.check_cancelled();

  EstimateNormalsResult result;
  // The orientation's weights need unit normals: a point with none gets a
  // zero normal, which no neighbour's sign can change.
  std::size_t undefined = 0;
  for (Row& r : rows) {
    const Kernel::Vector_3 n = std::get<1>(r);
    const double len = std::sqrt(n.squared_length());
    if (std::isfinite(len) && len > 0) std::get<1>(r) = n / len;
    else {
      std::get<1>(r) = Kernel::Vector_3(0, 0, 0);
      ++undefined;
    }
  }
  if (undefined > 0)
    result.warnings.push_back(std::to_string(undefined) + " point" + (undefined == 1 ? "" : "s") +
                              " got no normal (a zero one): their neighbours coincide or lie on a line");

  if (p.orient) {
    ctx.progress(0.6, "orientation");
    const auto first_unoriented = CGAL::mst_orient_normals(rows, k, params);
    const auto unoriented = std::size_t(rows.end() - first_unoriented);
    if (unoriented > 0)
      result.warnings.push_back(std::to_string(unoriented) + " of " + std::to_string(rows.size()) +
                                " points could not be oriented (the neighbour graph does not reach them, or their "
                                "normals turn too sharply): their normals keep the fit's arbitrary sign; more "
                                "neighbours may join them");
    ctx.check_cancelled();
  }

  result.points = cloud;
  result.points.normals.assign(cloud.size(), Vec3f{});
  for (const Row& r : rows) {
    const Kernel::Vector_3& n = std::get<1>(r);
    result.points.normals[std::get<2>(r)] = {float(n.x()), float(n.y()), float(n.z())};
  }
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(
    estimate_normals,
    [](const Inputs& in, const EstimateNormalsParams& p, Context* c) {
      return estimate_normals(in.points("points"), p, c);
    },
    {.title = "Estimate normals",
     .description = "A normal at each point from its nearest neighbours (CGAL's jet fitting or PCA), then one "
                    "consistent side, outward on a closed surface (CGAL's mst_orient_normals).",
     .area = "points",
     .inputs = {{.name = "points",
                 .kind = OutputKind::points,
                 .help = "the point cloud (a mesh's vertices may stand for one)"}}})

}  // namespace cgview
