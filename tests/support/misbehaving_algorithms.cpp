// Algorithms that misbehave on purpose, for the job scheduler's tests.
// Linked only into cgview-worker-test (area "test"), never into the server,
// the CLI or the normal worker.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <thread>
#include <vector>

#include "registry/registry.h"

namespace cgview {
namespace {

struct NoParams {
  template <class V>
  void describe(V&) {}
};

AlgorithmResult segfault(const Mesh&, const NoParams&, Context&) {
  std::raise(SIGSEGV);
  return {};
}

AlgorithmResult memory_hog(const Mesh&, const NoParams&, Context& ctx) {
  std::vector<char*> blocks;
  for (;;) {
    char* p = new char[64 << 20];
    std::memset(p, 1, 64 << 20);  // touch it, so it counts
    blocks.push_back(p);
    ctx.progress(0.5, "allocating");
  }
}

struct SleepParams {
  double seconds = 30;
  template <class V>
  void describe(V& v) {
    v.number("seconds", seconds, {.label = "Seconds", .min = 0, .max = 3600, .help = "how long to run"});
  }
};

AlgorithmResult sleeper(const Mesh& mesh, const SleepParams& p, Context& ctx) {
  const auto start = std::chrono::steady_clock::now();
  const auto total = std::chrono::duration<double>(p.seconds);
  for (;;) {
    const auto done = std::chrono::steady_clock::now() - start;
    if (done >= total) break;
    ctx.check_cancelled();
    ctx.progress(std::chrono::duration<double>(done) / total, "sleeping");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ScalarField f{"index", Location::vertex, ColorHint::standard, {}};
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) f.values.push_back(float(i));
  return {{{"index", f}}, {}};
}

// The input moved by +1 along x: a mesh output, for chained jobs.
AlgorithmResult translate(const Mesh& mesh, const NoParams&, Context&) {
  Mesh out;
  out.positions = mesh.positions;
  out.faces = mesh.faces;
  for (Vec3& p : out.positions) p.x += 1.0;
  return {{{"mesh", out}}, {}};
}

// The cloud it is given moved by +1 along x, and what it was given (how many
// points, with normals, with colours): what the worker hands an input of
// kind points, from a stored mesh or an earlier job's points or mesh.
AlgorithmResult move_points(const Inputs& in, const NoParams&, Context&) {
  PointCloud out = in.points("points");
  Metrics m{{"points", double(out.size())},
            {"normals", out.has_normals() ? 1.0 : 0.0},
            {"colors", out.has_colors() ? 1.0 : 0.0},
            {"min_x", out.positions.empty() ? 0.0 : out.positions[0].x}};
  for (Vec3& p : out.positions) {
    m["min_x"] = std::min(m["min_x"], p.x);
    p.x += 1.0;
  }
  return {{{"points", std::move(out)}, {"given", std::move(m)}}, {}};
}

// Prints to stdout as libraries and students' code do: that must not reach
// the worker's progress pipe, or the job would fail for it.
AlgorithmResult chatty(const Mesh& mesh, const NoParams&, Context& ctx) {
  std::printf("iteration 1 of 3: residual 0.25\nprogress banana\n");
  std::cout << "a line from std::cout without an end" << std::flush;
  ctx.progress(0.5, "chatting\non two lines");
  std::fflush(stdout);
  ScalarField f{"index", Location::vertex, ColorHint::standard, {}};
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) f.values.push_back(float(i));
  return {{{"index", f}}, {}};
}

CGVIEW_REGISTER_ALGORITHM(test_chatty, NoParams, chatty,
                          {.title = "Chatty (test)",
                           .description = "prints to stdout while it runs",
                           .area = "test",
                           .outputs = {{"index", OutputKind::scalar_field}}})
CGVIEW_REGISTER_ALGORITHM(test_translate, NoParams, translate,
                          {.title = "Translate (test)",
                           .description = "moves the mesh by +1 in x",
                           .area = "test",
                           .outputs = {{"mesh", OutputKind::mesh}}})
CGVIEW_REGISTER_ALGORITHM(test_points, NoParams, move_points,
                          {.title = "Move points (test)",
                           .description = "moves the point cloud by +1 in x",
                           .area = "test",
                           .outputs = {{"points", OutputKind::points}, {"given", OutputKind::metrics}},
                           .inputs = {{.name = "points", .kind = OutputKind::points, .help = "the cloud to move"}}})
CGVIEW_REGISTER_ALGORITHM(test_segfault, NoParams, segfault,
                          {.title = "Crash (test)", .description = "raises SIGSEGV", .area = "test", .outputs = {}})
CGVIEW_REGISTER_ALGORITHM(
    test_memory_hog, NoParams, memory_hog,
    {.title = "Memory hog (test)", .description = "allocates without bound", .area = "test", .outputs = {}})
CGVIEW_REGISTER_ALGORITHM(test_sleep, SleepParams, sleeper,
                          {.title = "Sleep (test)",
                           .description = "runs for a while, checking for cancellation",
                           .area = "test",
                           .outputs = {{"index", OutputKind::scalar_field}}})

}  // namespace
}  // namespace cgview
