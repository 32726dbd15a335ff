// The map parameters shared by chaos_map and chaos_animate: their labels,
// ranges and help live here once.
#pragma once

#include <string>

#include "chaos/maps.h"
#include "registry/registry.h"

namespace cgview::chaos {

struct MapParamFields {
  std::string map = "ikeda";
  double u = 0.9, r = 3.99, a = 1.4, b = 0.3;
  int grid = 1024;
  template <class V>
  void describe_map(V& v) {
    v.choice("map", map,
             {.label = "Map",
              .help = "ikeda (u) on (x, y); cat (grid) on (x, y); logistic (r) on each coordinate; henon (a, b) on "
                      "(x, y); composite: Ikeda on (x, y), (y, z), (z, x)",
              .choices = {"ikeda", "cat", "logistic", "henon", "composite"}});
    v.number("u", u,
             {.label = "Ikeda u",
              .min = 0,
              .max = 1,
              .help = "Ikeda's parameter; chaotic near 0.9",
              .when = {"map", {"ikeda", "composite"}}});
    v.number("r", r,
             {.label = "Logistic r",
              .min = 0,
              .max = 4,
              .help = "logistic map's parameter; chaotic near 4",
              .when = {"map", {"logistic"}}});
    v.number("a", a,
             {.label = "Henon a", .min = 0, .max = 2, .help = "Henon's a (classic 1.4)", .when = {"map", {"henon"}}});
    v.number("b", b,
             {.label = "Henon b", .min = -1, .max = 1, .help = "Henon's b (classic 0.3)", .when = {"map", {"henon"}}});
    v.integer("grid", grid,
              {.label = "Cat grid N",
               .min = 2,
               .max = 1 << 20,
               .help = "the cat map acts on an N x N grid of the (x, y) box; its period is the Pisano period of N / 2",
               .when = {"map", {"cat"}}});
  }
  MapParams map_params() const {
    MapParams p;
    p.map = map_kind_from_string(map);
    p.u = u, p.r = r, p.a = a, p.b = b;
    p.grid = std::uint32_t(grid);
    return p;
  }
};

}  // namespace cgview::chaos
