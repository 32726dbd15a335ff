#include "chaos/chaos_animate.h"

#include <cmath>
#include <string>

#include "chaos/maps.h"

namespace cgview {

ChaosAnimateResult chaos_animate(const Mesh& mesh, const ChaosAnimateParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_vertices() == 0) throw InvalidInput("chaos_animate: the mesh has no vertices");
  // A frame costs 6 bytes a vertex in the .frames file: keep a job's output
  // under about 1.2 GB.
  if (double(mesh.num_vertices()) * p.frames > 2e8)
    throw InvalidInput("parameter 'frames': " + std::to_string(p.frames) + " frames of " +
                       std::to_string(mesh.num_vertices()) + " vertices exceed 2e8 positions; ask for fewer frames");
  const chaos::MapParams& mp = p.map;
  const chaos::Normalization norm = chaos::normalization_for(mesh.positions, mp.kind);
  std::vector<Vec3> q(mesh.num_vertices());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = norm.to_normalized(mesh.positions[i]);
  // Frame 0 is the input as it is; cat works on grid cells, so its first
  // step starts from the snapped positions (chaos::apply_map does the same).
  if (mp.kind == chaos::MapKind::cat)
    for (Vec3& v : q) {
      const auto cell = [&](double x) {
        const double c = std::floor(x * mp.grid);
        return c < 0 ? 0.0 : c >= mp.grid ? double(mp.grid - 1) : c;
      };
      v.x = (cell(v.x) + 0.5) / mp.grid, v.y = (cell(v.y) + 0.5) / mp.grid;
    }
  ChaosAnimateResult result;
  Animation& anim = result.animation;
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
  std::size_t n_escaped = 0;
  for (auto e : escaped) n_escaped += e;
  if (n_escaped > 0)
    result.warnings.push_back(std::to_string(n_escaped) +
                              " vertices left every bound (outside the map's basin) and were frozen");
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(chaos_animate, chaos_animate,
                         {.title = "Chaotic map animation",
                          .description = "Frames of the vertex positions after 1..K steps of a chaotic map "
                                         "(Ikeda, cat, logistic, Henon, composite), played in the viewer with a "
                                         "slider: the CGView paper's Figure 11.",
                          .area = "chaos"})

}  // namespace cgview
