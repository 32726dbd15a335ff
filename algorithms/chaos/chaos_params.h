// The map parameters shared by chaos_map and chaos_animate: their labels,
// ranges and help live here once, their defaults in chaos::MapParams
// (chaos/maps.h).  Each algorithm's params hold a MapParams named `map`:
//   chaos_map(mesh, {.map = {.kind = chaos::MapKind::henon, .a = 1.2}, .steps = 20});
#pragma once

#include "chaos/maps.h"
#include "registry/registry.h"

namespace cgview::chaos {

template <class V>
void describe_map(V& v, MapParams& m) {
  v.choice("map", m.kind,
           {.label = "Map",
            .help = "ikeda (u) on (x, y); cat (grid) on (x, y); logistic (r) on each coordinate; henon (a, b) on "
                    "(x, y); composite: Ikeda on (x, y), (y, z), (z, x)",
            .choices = {"ikeda", "cat", "logistic", "henon", "composite"}});
  v.number("u", m.u,
           {.label = "Ikeda u",
            .min = 0,
            .max = 1,
            .help = "Ikeda's parameter; chaotic near 0.9",
            .when = {"map", {"ikeda", "composite"}}});
  v.number("r", m.r,
           {.label = "Logistic r",
            .min = 0,
            .max = 4,
            .help = "logistic map's parameter; chaotic near 4",
            .when = {"map", {"logistic"}}});
  v.number("a", m.a,
           {.label = "Henon a", .min = 0, .max = 2, .help = "Henon's a (classic 1.4)", .when = {"map", {"henon"}}});
  v.number("b", m.b,
           {.label = "Henon b", .min = -1, .max = 1, .help = "Henon's b (classic 0.3)", .when = {"map", {"henon"}}});
  v.integer("grid", m.grid,
            {.label = "Cat grid N",
             .min = 2,
             .max = 1 << 20,
             .help = "the cat map acts on an N x N grid of the (x, y) box; its period is the Pisano period of N / 2",
             .when = {"map", {"cat"}}});
}

}  // namespace cgview::chaos
