// chaos_animate: the positions after 1..K steps of a chaotic map, as frames
// of an animation the viewer plays with a slider (the CGView paper's
// Figure 11 as a film).  Saved and served as .frames (core/animation.h).
#include <cmath>
#include <string>

#include "chaos/chaos_params.h"
#include "chaos/maps.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct Params : chaos::MapParamFields {
  int frames = 30;
  int steps_per_frame = 1;
  template <class V>
  void describe(V& v) {
    describe_map(v);
    v.integer("frames", frames, {.label = "Frames", .min = 1, .max = 500, .help = "K: frames after 1..K steps"});
    v.integer("steps_per_frame", steps_per_frame,
              {.label = "Steps per frame", .min = 1, .max = 100, .help = "map steps between two frames"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_vertices() == 0) throw InvalidInput("chaos_animate: the mesh has no vertices");
  // A frame costs 6 bytes a vertex in the .frames file: keep a job's output
  // under about 1.2 GB.
  if (double(mesh.num_vertices()) * p.frames > 2e8)
    throw InvalidInput("parameter 'frames': " + std::to_string(p.frames) + " frames of " +
                       std::to_string(mesh.num_vertices()) + " vertices exceed 2e8 positions; ask for fewer frames");
  const chaos::MapParams mp = p.map_params();
  if (mp.map == chaos::MapKind::cat && mp.grid < 2) throw InvalidInput("parameter 'grid': must be 2 or more");
  const chaos::Normalization norm = chaos::normalization_for(mesh.positions, mp.map);
  std::vector<Vec3> q(mesh.num_vertices());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = norm.to_normalized(mesh.positions[i]);
  // Frame 0 is the input as it is; cat works on grid cells, so its first
  // step starts from the snapped positions (chaos::apply_map does the same).
  if (mp.map == chaos::MapKind::cat)
    for (Vec3& v : q) {
      const auto cell = [&](double x) {
        const double c = std::floor(x * mp.grid);
        return c < 0 ? 0.0 : c >= mp.grid ? double(mp.grid - 1) : c;
      };
      v.x = (cell(v.x) + 0.5) / mp.grid, v.y = (cell(v.y) + 0.5) / mp.grid;
    }
  Animation anim;
  anim.base.positions = mesh.positions;
  anim.base.faces = mesh.faces;
  std::vector<std::uint8_t> escaped;
  for (int f = 0; f < p.frames; ++f) {
    ctx.check_cancelled();
    ctx.progress(double(f) / p.frames, "frames");
    for (int s = 0; s < p.steps_per_frame; ++s) chaos::map_one_step(q, mp, escaped);
    std::vector<Vec3f> frame(q.size());
    for (std::size_t i = 0; i < q.size(); ++i) frame[i] = to_float(norm.from_normalized(q[i]));
    anim.frames.push_back(std::move(frame));
  }
  AlgorithmResult result;
  std::size_t n_escaped = 0;
  for (auto e : escaped) n_escaped += e;
  if (n_escaped > 0)
    result.warnings.push_back(std::to_string(n_escaped) +
                              " vertices left every bound (outside the map's basin) and were frozen");
  result.artifacts.push_back({"animation", std::move(anim)});
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(chaos_animate, Params, run,
                          {.title = "Chaotic map animation",
                           .description = "Frames of the vertex positions after 1..K steps of a chaotic map "
                                          "(Ikeda, cat, logistic, Henon, composite), played in the viewer with a "
                                          "slider: the CGView paper's Figure 11.",
                           .area = "chaos",
                           .outputs = {{"animation", OutputKind::animation}}})

}  // namespace
}  // namespace cgview
