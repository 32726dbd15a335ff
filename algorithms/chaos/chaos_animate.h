// chaos_animate: the positions after 1..K steps of a chaotic map, as frames
// of an animation the viewer plays with a slider (the CGView paper's
// Figure 11 as a film).  Saved and served as .frames (core/animation.h).
//
//   Mesh m = read_mesh("bunny.off");
//   ChaosAnimateResult r = chaos_animate(m, {.map = {.kind = chaos::MapKind::henon}, .frames = 30});
//   write_file_bytes("henon.frames", encode_frames(r.animation));
#pragma once

#include <string>
#include <vector>

#include "chaos/chaos_params.h"
#include "core/animation.h"
#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct ChaosAnimateParams {
  chaos::MapParams map{};
  int frames = 30;
  int steps_per_frame = 1;
  template <class V>
  void describe(V& v) {
    chaos::describe_map(v, map);
    v.integer("frames", frames, {.label = "Frames", .min = 1, .max = 500, .help = "K: frames after 1..K steps"});
    v.integer("steps_per_frame", steps_per_frame,
              {.label = "Steps per frame", .min = 1, .max = 100, .help = "map steps between two frames"});
  }
};

struct ChaosAnimateResult {
  Animation animation;  // base: the input's positions and faces; frames: after 1..K steps
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("animation", animation);
  }
};

// Throws InvalidInput for a mesh without vertices, or frames x vertices
// over 2e8 (a frame costs 6 bytes a vertex in the .frames file).
ChaosAnimateResult chaos_animate(const Mesh& mesh, const ChaosAnimateParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
