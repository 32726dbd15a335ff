// Everyday filters: each filter run through the registry
// (find_algorithm(name).run, which converts Mesh -> Surface_mesh -> Mesh)
// against a direct call of the same CGAL function with the same settings on
// a CGAL::Surface_mesh already in memory (converted once, outside the
// timing).  Meshes: the largest sample and a 1.2M-triangle mesh (bunny00
// subdivided twice); fill_holes runs on elephant-with-holes.off.  Prints a
// Markdown table with the ratio.
//
//   build/bin/filters_bench [--repeat N] [--quick]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/surface_mesh.h"
#include "filters_direct.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "registry/registry.h"

using namespace cgview;
using bench::best_seconds;
using bench::mean_edge_length;

namespace {

std::size_t result_faces(const AlgorithmResult& r) {
  for (const Artifact& a : r.artifacts)
    if (const Mesh* m = std::get_if<Mesh>(&a.value)) return m->num_faces();
  return 0;
}

struct Input {
  std::string name;
  Mesh mesh;
  bool large;
};

struct Filter {
  std::string name;
  std::string settings;
  std::map<std::string, ParamValue> params;
  std::function<void(SurfaceMesh&)> direct;
  bool holes_only = false;  // runs on elephant-with-holes only
  bool skip_large = false;  // over ~20 s a run on the 1.2M-triangle mesh (measured: smooth 21 s)
};

}  // namespace

int main(int argc, char** argv) {
  const bench::Options options = bench::parse_options(argc, argv, "filters_bench");
  const int repeat = options.repeat;
  const bool quick = options.quick;
  const auto elephant = resolve_mesh_path("refined_elephant.off");
  const auto holes = resolve_mesh_path("elephant-with-holes.off");
  const auto base = resolve_mesh_path("bunny00.off");
  if (!elephant || !holes || !base) {
    std::fprintf(stderr, "filters_bench: sample meshes not found (install libcgal-demo, re-run cmake)\n");
    return 1;
  }
  std::vector<Input> inputs;
  inputs.push_back({"refined_elephant", read_mesh(*elephant), false});
  if (!quick)
    inputs.push_back({"bunny00 subdivided twice", subdivide_midpoint(subdivide_midpoint(read_mesh(*base))), true});
  const Input holes_input{"elephant-with-holes", read_mesh(*holes), false};

  // Each direct call mirrors the CGAL calls of its filter in
  // algorithms/filters/, with the same settings (the filters' defaults where
  // the table does not name one).
  std::vector<Filter> filters;
  filters.push_back({"simplify", "ratio 0.25", {{"ratio", 0.25}}, bench::direct_simplify, false, false});
  filters.push_back(
      {"remesh", "1 iteration, mean edge length", {{"iterations", 1LL}}, bench::direct_remesh, false, false});
  filters.push_back({"smooth",
                     "mean_curvature_flow, 1 iteration",
                     {{"method", std::string("mean_curvature_flow")}, {"iterations", 1LL}},
                     bench::direct_smooth,
                     false,
                     true});
  filters.push_back({"subdivide",
                     "loop, 1 iteration",
                     {{"method", std::string("loop")}, {"iterations", 1LL}},
                     bench::direct_subdivide,
                     false,
                     false});
  filters.push_back({"normals", "", {}, bench::direct_normals, false, false});
  filters.push_back({"geodesic_distance",
                     "heat method, intrinsic Delaunay, source vertex 0",
                     {},
                     bench::direct_geodesic_distance,
                     false,
                     false});
  filters.push_back(
      {"components", "keep_largest", {{"mode", std::string("keep_largest")}}, bench::direct_components, false, false});
  filters.push_back(
      {"fill_holes", "refine_and_fair, holes up to 1000 edges", {}, bench::direct_fill_holes, true, false});

  // The conversions every filter pays, Mesh -> Surface_mesh (CGAL's add_face,
  // face by face) and back: most of the overhead of the light filters.
  if (options.wants("conversion")) {
    std::printf("| conversion | mesh | triangles | to_surface_mesh s | from_surface_mesh s |\n");
    std::printf("|---|---|---:|---:|---:|\n");
    for (const Input& in : inputs) {
      SurfaceMesh sm;
      const double to = best_seconds(
          repeat, [&] { sm.clear(); }, [&] { sm = to_surface_mesh(in.mesh).mesh; });
      const double back = best_seconds(
          repeat, [] {}, [&] { (void)from_surface_mesh(sm); });
      std::printf("| Mesh <-> Surface_mesh | %s | %zu | %.3f | %.3f |\n", in.name.c_str(), in.mesh.num_faces(), to,
                  back);
      std::fflush(stdout);
    }
    std::printf("\n");
  }

  std::printf("| filter | settings | mesh | triangles | registry s | direct CGAL s | registry / direct |\n");
  std::printf("|---|---|---|---:|---:|---:|---:|\n");
  std::fflush(stdout);
  for (const Filter& f : filters) {
    if (!options.wants(f.name)) continue;
    const Algorithm& algo = find_algorithm(f.name);
    std::vector<const Input*> runs;
    if (f.holes_only) runs.push_back(&holes_input);
    else
      for (const Input& in : inputs) runs.push_back(&in);
    for (const Input* in : runs) {
      if (in->large && f.skip_large) {
        std::printf("| %s | %s | %s | %zu | skipped (over 20 s a run) | skipped | - |\n", f.name.c_str(),
                    f.settings.c_str(), in->name.c_str(), in->mesh.num_faces());
        std::fflush(stdout);
        continue;
      }
      std::map<std::string, ParamValue> params = f.params;
      const SurfaceMesh converted = to_surface_mesh(in->mesh).mesh;  // once, outside the timing
      if (f.name == "remesh") params["target_edge_length"] = mean_edge_length(converted);
      Context ctx;
      std::size_t reg_faces = 0;
      const double reg = best_seconds(
          repeat, [] {}, [&] { reg_faces = result_faces(algo.run(in->mesh, params, ctx)); });
      SurfaceMesh sm;
      const double direct = best_seconds(
          repeat, [&] { sm = converted; }, [&] { f.direct(sm); });
      if (reg_faces > 0 && reg_faces != sm.number_of_faces())
        std::fprintf(stderr, "note: %s on %s: registry gave %zu faces, direct call %zu\n", f.name.c_str(),
                     in->name.c_str(), reg_faces, std::size_t(sm.number_of_faces()));
      std::printf("| %s | %s | %s | %zu | %.3f | %.3f | %.2fx |\n", f.name.c_str(), f.settings.c_str(),
                  in->name.c_str(), in->mesh.num_faces(), reg, direct, reg / direct);
      std::fflush(stdout);
    }
  }

  // hausdorff takes two meshes: each input against a copy of itself moved by
  // 0.5% of its bounding-box diagonal. Direct: CGAL's bounded-error Hausdorff
  // distance both ways, the same error bound. The registry also computes each
  // vertex's distance (the colour map): the ratio says what that costs.
  if (options.wants("hausdorff")) {
    const Algorithm& algo = find_algorithm("hausdorff");
    for (const Input& in : inputs) {
      const double diagonal = bounding_box(in.mesh).diagonal();
      Mesh moved = in.mesh;
      for (Vec3& p : moved.positions) p.x += 0.005 * diagonal;
      Inputs both;
      both.add("mesh", in.mesh);
      both.add("reference", moved);
      Context ctx;
      double reg_value = 0;
      const double reg = best_seconds(
          repeat, [] {},
          [&] {
            const AlgorithmResult r = algo.run(both, {}, ctx);
            reg_value = std::get<Metrics>(r.artifacts.back().value).at("hausdorff");
          });
      const SurfaceMesh a = to_surface_mesh(in.mesh).mesh, b = to_surface_mesh(moved).mesh;
      BBox box = bounding_box(in.mesh);
      for (const Vec3& p : moved.positions) box.add(p);
      const double bound = 1e-4 * box.diagonal();
      double direct_value = 0;
      const double direct = best_seconds(
          repeat, [] {}, [&] { direct_value = bench::direct_hausdorff(a, b, bound); });
      if (std::abs(reg_value - direct_value) > 2 * bound)
        std::fprintf(stderr, "note: hausdorff on %s: registry %.6g, direct %.6g\n", in.name.c_str(), reg_value,
                     direct_value);
      std::printf(
          "| hausdorff | against itself moved 0.5%% of the diagonal, error bound 1e-4 | %s | %zu | %.3f | %.3f | %.2fx "
          "|\n",
          in.name.c_str(), in.mesh.num_faces(), reg, direct, reg / direct);
      std::fflush(stdout);
    }
  }

  // repair starts from a polygon soup: the direct side gets the soup made
  // outside the timing, then the same CGAL calls as algorithms/filters/repair.cpp.
  if (options.wants("repair")) {
    const Algorithm& algo = find_algorithm("repair");
    for (const Input& in : inputs) {
      Context ctx;
      const double reg = best_seconds(
          repeat, [] {}, [&] { (void)algo.run(in.mesh, {}, ctx); });
      std::vector<Point3> points;
      std::vector<std::vector<std::size_t>> polygons;
      SurfaceMesh sm;
      const double direct = best_seconds(
          repeat,
          [&] {
            points.clear();
            polygons.clear();
            sm.clear();
            for (const Vec3& v : in.mesh.positions) points.emplace_back(v.x, v.y, v.z);
            for (const Tri& f : in.mesh.faces) polygons.push_back({f[0], f[1], f[2]});
          },
          [&] { bench::direct_repair(points, polygons, sm); });
      std::printf("| repair | soup repair, orient, stitch | %s | %zu | %.3f | %.3f | %.2fx |\n", in.name.c_str(),
                  in.mesh.num_faces(), reg, direct, reg / direct);
      std::fflush(stdout);
    }
  }
  return 0;
}
