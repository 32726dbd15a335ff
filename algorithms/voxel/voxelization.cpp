// The voxelization itself (voxel/voxelize.h explains the rules): in the
// library cgview_voxelize, which skeleton_projection's solid uses too; the
// algorithm voxelize (voxel/voxelize.cpp) checks its parameters, then calls
// voxelize_unchecked.
#include "voxel/voxelize.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <numeric>

#include "core/union_find.h"
#include "core/errors.h"
#include "core/threads.h"
#include "registry/registry.h"

namespace cgview {
namespace {

std::string format_bytes(double b) {
  char buf[64];
  if (b >= 1024.0 * 1024 * 1024) std::snprintf(buf, sizeof buf, "%.1f GB", b / (1024.0 * 1024 * 1024));
  else std::snprintf(buf, sizeof buf, "%.1f MB", b / (1024.0 * 1024));
  return buf;
}

// Boundary edges (used by one face) and the loops they form.  Each
// undirected edge (a < b) goes into a's bucket (a counting sort, O(faces));
// an edge found once in its bucket is a boundary edge.  Faster than
// edge_topology(), which builds the whole edge-face adjacency.
void count_boundary(const Mesh& mesh, std::size_t& edges, std::size_t& loops) {
  const std::size_t nv = mesh.num_vertices();
  std::vector<std::uint32_t> start(nv + 1, 0);
  for (const Tri& t : mesh.faces)
    for (int c = 0; c < 3; ++c) {
      const Index a = t[c], b = t[(c + 1) % 3];
      if (a != b) ++start[std::min(a, b) + 1];
    }
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> other(start[nv]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (const Tri& t : mesh.faces)
    for (int c = 0; c < 3; ++c) {
      const Index a = t[c], b = t[(c + 1) % 3];
      if (a != b) other[fill[std::min(a, b)]++] = std::max(a, b);
    }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> border;
  for (std::uint32_t v = 0; v < nv; ++v) {
    std::uint32_t* first = other.data() + start[v];
    std::uint32_t* last = other.data() + start[v + 1];
    std::sort(first, last);  // a handful each
    for (std::uint32_t* i = first; i != last;) {
      std::uint32_t* j = i + 1;
      while (j != last && *j == *i) ++j;
      if (j - i == 1) border.push_back({v, *i});
      i = j;
    }
  }
  edges = border.size();
  std::vector<std::uint32_t> verts;  // boundary vertices, for the loops
  for (const auto& [p, q] : border) verts.push_back(p), verts.push_back(q);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  UnionFind sets(verts.size());
  auto id = [&](std::uint32_t v) {
    return std::uint32_t(std::lower_bound(verts.begin(), verts.end(), v) - verts.begin());
  };
  for (const auto& [p, q] : border) sets.unite(id(p), id(q));
  loops = 0;
  for (std::uint32_t v = 0; v < sets.parent.size(); ++v) loops += sets.find(v) == v;
}

// A run of empty voxels [x0, x1] in one row (j, k) of the grid.
struct Run {
  int x0, x1;
};

// Marks as occupied the empty voxels that a 6-connected flood of empty
// voxels from the border does not reach.  The flood runs over runs of empty
// voxels along x rather than over voxels, so its cost follows the surface
// (a few runs per row), not the volume.  Returns the voxels added.
std::size_t fill_interior(VoxelGrid& g, int threads, const Context* ctx) {
  const auto d = g.dims();
  const std::size_t nx = std::size_t(d[0]), rows = std::size_t(d[1]) * d[2];
  std::uint8_t* bytes = g.bytes().data();

  // Runs per row, built in parallel over blocks of rows, then concatenated.
  const int nt = std::max(1, std::min<int>(threads, int(rows)));
  std::vector<std::vector<Run>> part_runs(nt);
  std::vector<std::vector<std::uint32_t>> part_counts(nt);
  auto build = [&](int t) {
    const std::size_t r0 = rows * t / nt, r1 = rows * (t + 1) / nt;
    auto& runs = part_runs[t];
    auto& counts = part_counts[t];
    counts.reserve(r1 - r0);
    for (std::size_t r = r0; r < r1; ++r) {
      const std::uint8_t* row = bytes + r * nx;
      const std::size_t before = runs.size();
      std::size_t x = 0;
      while (x < nx) {
        const void* z = std::memchr(row + x, 0, nx - x);  // next empty voxel
        if (!z) break;
        const std::size_t a = std::size_t(static_cast<const std::uint8_t*>(z) - row);
        const void* o = std::memchr(row + a, 1, nx - a);  // next occupied one
        const std::size_t b = o ? std::size_t(static_cast<const std::uint8_t*>(o) - row) : nx;
        runs.push_back({int(a), int(b - 1)});
        x = b;
      }
      counts.push_back(std::uint32_t(runs.size() - before));
    }
  };
  on_threads(nt, build);
  if (ctx) ctx->check_cancelled();
  std::vector<std::size_t> offset(rows + 1, 0);
  std::vector<Run> runs;
  {
    std::size_t total = 0;
    for (auto& p : part_runs) total += p.size();
    runs.reserve(total);
    std::size_t r = 0;
    for (int t = 0; t < nt; ++t) {
      for (std::uint32_t c : part_counts[t]) {
        offset[r + 1] = offset[r] + c;
        ++r;
      }
      runs.insert(runs.end(), part_runs[t].begin(), part_runs[t].end());
      std::vector<Run>().swap(part_runs[t]);
    }
  }
  if (ctx) ctx->progress(0.75, "flood fill");

  // Breadth-first over runs: seeds are the runs on the grid's border.
  std::vector<std::uint8_t> outside(runs.size(), 0);
  std::vector<std::uint32_t> stack;
  std::vector<std::uint32_t> run_row(runs.size());
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t q = offset[r]; q < offset[r + 1]; ++q) run_row[q] = std::uint32_t(r);
  const int ny = d[1], nz = d[2];
  for (std::size_t r = 0; r < rows; ++r) {
    const int j = int(r % ny), k = int(r / ny);
    const bool border_row = j == 0 || k == 0 || j == ny - 1 || k == nz - 1;
    for (std::size_t q = offset[r]; q < offset[r + 1]; ++q)
      if (border_row || runs[q].x0 == 0 || runs[q].x1 == int(nx) - 1) {
        outside[q] = 1;
        stack.push_back(std::uint32_t(q));
      }
  }
  while (!stack.empty()) {
    const std::uint32_t q = stack.back();
    stack.pop_back();
    const Run run = runs[q];
    const std::size_t r = run_row[q];
    const int j = int(r % ny), k = int(r / ny);
    const long long nbr[4] = {j > 0 ? (long long)r - 1 : -1, j < ny - 1 ? (long long)r + 1 : -1,
                              k > 0 ? (long long)r - ny : -1, k < nz - 1 ? (long long)r + ny : -1};
    for (long long s : nbr) {
      if (s < 0) continue;
      // The first run of row s ending at or after run.x0, then those overlapping.
      const Run* first = runs.data() + offset[s];
      const Run* last = runs.data() + offset[s + 1];
      const Run* it = std::lower_bound(first, last, run.x0, [](const Run& a, int x) { return a.x1 < x; });
      for (; it != last && it->x0 <= run.x1; ++it) {
        const std::size_t idx = std::size_t(it - runs.data());
        if (!outside[idx]) {
          outside[idx] = 1;
          stack.push_back(std::uint32_t(idx));
        }
      }
    }
  }
  if (ctx) ctx->check_cancelled();
  std::size_t added = 0;
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t q = offset[r]; q < offset[r + 1]; ++q)
      if (!outside[q]) {
        std::memset(bytes + r * nx + runs[q].x0, 1, std::size_t(runs[q].x1 - runs[q].x0 + 1));
        added += std::size_t(runs[q].x1 - runs[q].x0 + 1);
      }
  return added;
}

}  // namespace

double voxelize_memory_bytes(std::array<int, 3> dims) {
  // One byte per voxel; the flood's runs and flags are a small fraction.
  return double(dims[0]) * double(dims[1]) * double(dims[2]) * 1.0;
}

VoxelizeGeometry voxelize_geometry(const BBox& box, const VoxelizeParams& p) {
  const Vec3 ext = box.size();
  const double longest = std::max({ext.x, ext.y, ext.z});
  const double size = p.voxel_size > 0 ? p.voxel_size : longest / p.resolution;
  if (!(size > 0)) throw InvalidInput("the mesh's bounding box is a single point: give a voxel_size to voxelize it");
  std::array<int, 3> dims{};
  double voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::max(1.0, std::ceil(ext[a] / size * (1 - 1e-12)));
    const double n = cells + 2.0 * p.padding;
    voxels *= n;
    dims[a] = n < 2e9 ? int(n) : 2000000000;
  }
  const double need = voxels;  // voxelize_memory_bytes, without int overflow
  if (need > p.max_memory_mb * 1024 * 1024) {
    char shape[128];
    std::snprintf(shape, sizeof shape, "%.0fx%.0fx%.0f",
                  std::max(1.0, std::ceil(ext.x / size * (1 - 1e-12))) + 2.0 * p.padding,
                  std::max(1.0, std::ceil(ext.y / size * (1 - 1e-12))) + 2.0 * p.padding,
                  std::max(1.0, std::ceil(ext.z / size * (1 - 1e-12))) + 2.0 * p.padding);
    throw InvalidInput(std::string("parameter '") + (p.voxel_size > 0 ? "voxel_size" : "resolution") + "': a " + shape +
                       " grid would take " + format_bytes(need) +
                       ", over the limit max_memory_mb = " + std::to_string(long(p.max_memory_mb)) + " MB");
  }
  return {dims, size, need};
}

VoxelizeResult voxelize_unchecked(const Mesh& mesh, const VoxelizeParams& p, const Context* ctx) {
  // A mesh with no faces is a point cloud (as files hold one): its points
  // mark voxels, and it has no inside to fill.
  const bool cloud = mesh.num_faces() == 0;
  if (cloud && mesh.num_vertices() == 0) throw InvalidInput("voxelize: the mesh is empty (no faces, no points)");
  if (cloud && p.mode == VoxelizeMode::solid)
    throw InvalidInput(
        "voxelize: a point cloud (a mesh with no faces) has no inside to fill: use mode surface (each point marks "
        "its voxel), or make a surface of it first (poisson_reconstruction)");
  mesh.validate();
  // Only the vertices that faces use count for the box (a cloud's: all).
  BBox box;
  if (cloud)
    for (const Vec3& q : mesh.positions) box.add(q);
  for (const Tri& t : mesh.faces)
    for (Index v : t) box.add(mesh.positions[v]);
  if (p.box) {
    // Up to rounding (a decimated copy's vertices, means of the full mesh's,
    // can be an ulp past its box; the clamp below keeps them in).
    const double slack = 1e-9 * norm(p.box->size());
    for (int a = 0; a < 3; ++a)
      if (box.min[a] < p.box->min[a] - slack || box.max[a] > p.box->max[a] + slack)
        throw InvalidInput(std::string("voxelize: the given box does not hold the mesh's ") +
                           (cloud ? "points" : "faces"));
    box = *p.box;
  }
  const auto [dims, size, need] = voxelize_geometry(box, p);
  // The cells the box spans on each axis (dims without the padding).
  const double cells_of[3] = {double(dims[0] - 2 * p.padding), double(dims[1] - 2 * p.padding),
                              double(dims[2] - 2 * p.padding)};
  const Vec3 origin = box.min - Vec3{1, 1, 1} * (p.padding * size);
  VoxelizeResult result;
  result.grid = VoxelGrid(dims, origin, size, VoxelType::bit, std::uint64_t(need) + 1);
  if (ctx) ctx->progress(0.0, "surface voxels");

  // Vertices in grid coordinates, where voxel (i, j, k) is [i, i+1) x ...
  std::vector<Vec3> g(mesh.num_vertices());
  // Measured from the box's corner, so that the lowest vertex lands exactly on
  // the padding and rounding never marks a padding voxel (the clamp moves a
  // vertex by a rounding error at most): the padding stays empty.
  for (std::size_t v = 0; v < g.size(); ++v) {
    const Vec3 q = (mesh.positions[v] - box.min) / size;
    for (int a = 0; a < 3; ++a) g[v][a] = std::clamp(q[a], 0.0, cells_of[a]) + p.padding;
  }

  if (cloud) {
    // Voxel (i, j, k) is [i, i+1) x ...: a point marks the one holding it; a
    // point on the box's far side, the last voxel before the padding.
    std::uint8_t* bytes = result.grid.bytes().data();
    const std::size_t nx = std::size_t(dims[0]), nxy = nx * std::size_t(dims[1]);
    for (const Vec3& q : g) {
      std::size_t at = 0, stride = 1;
      for (int a = 0; a < 3; ++a) {
        const int last = p.padding + int(cells_of[a]) - 1;
        at += stride * std::size_t(std::min(int(std::floor(q[a])), last));
        stride = a == 0 ? nx : nxy;
      }
      bytes[at] = 1;
    }
    result.surface_voxels = result.solid_voxels = result.grid.count_occupied();
    if (ctx) ctx->progress(1.0, "done");
    return result;
  }

  int nt = p.threads > 0 ? p.threads : thread_count();
  nt = std::max(1, std::min(nt, 64));
  std::uint8_t* bytes = result.grid.bytes().data();
  const std::size_t nx = std::size_t(dims[0]), nxy = nx * std::size_t(dims[1]);
  const std::size_t nf = mesh.num_faces();
  constexpr std::size_t block = 4096;
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  auto work = [&](int t) {
    for (;;) {
      const std::size_t b0 = next.fetch_add(block);
      if (b0 >= nf || stop.load(std::memory_order_relaxed)) return;
      if (t == 0 && ctx) {
        if (ctx->cancelled()) {
          stop = true;
          return;
        }
        ctx->progress(0.7 * double(b0) / double(nf), "surface voxels");
      }
      const std::size_t b1 = std::min(nf, b0 + block);
      for (std::size_t f = b0; f < b1; ++f) {
        const Tri& tri = mesh.faces[f];
        for_each_triangle_voxel(g[tri[0]], g[tri[1]], g[tri[2]], dims, [&](int i, int j, int k) {
          // Threads may mark the same voxel: a relaxed atomic byte store.
          std::atomic_ref<std::uint8_t>(bytes[std::size_t(i) + nx * std::size_t(j) + nxy * std::size_t(k)])
              .store(1, std::memory_order_relaxed);
        });
      }
    }
  };
  on_threads(nt, work);
  if (stop) throw Cancelled();
  result.surface_voxels = result.grid.count_occupied();
  result.solid_voxels = result.surface_voxels;

  if (p.mode == VoxelizeMode::solid) {
    count_boundary(mesh, result.boundary_edges, result.boundary_loops);
    if (ctx) ctx->progress(0.7, "runs");
    const std::size_t added = fill_interior(result.grid, nt, ctx);
    result.solid_voxels += added;
    if (result.boundary_loops > 0) {
      std::string w = "the mesh is not closed: " + std::to_string(result.boundary_loops) + " boundary loop" +
                      (result.boundary_loops == 1 ? "" : "s") + " (" + std::to_string(result.boundary_edges) +
                      " boundary edges); the solid is what the surface voxels enclose (holes narrower than a voxel "
                      "are closed, wider ones let the outside in)";
      if (added == 0) w += "; here nothing was enclosed: the solid is only the surface voxels";
      result.warnings.push_back(std::move(w));
    }
  }
  if (ctx) ctx->progress(1.0, "done");
  return result;
}

}  // namespace cgview
