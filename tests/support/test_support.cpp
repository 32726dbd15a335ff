#include "test_support.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sys/wait.h>
#include <unistd.h>

namespace cgview::test {

namespace fs = std::filesystem;

Mesh box(Vec3 a, Vec3 b) {
  Mesh m;
  for (int k = 0; k < 8; ++k) m.positions.push_back({(k & 1) ? b.x : a.x, (k & 2) ? b.y : a.y, (k & 4) ? b.z : a.z});
  m.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

Mesh revolve(const std::vector<std::pair<double, double>>& profile, int segments) {
  Mesh m;
  m.positions.push_back({0, 0, profile.front().second});
  const int rings = int(profile.size()) - 2;
  for (int i = 1; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double a = 2 * std::numbers::pi * j / segments;
      m.positions.push_back({profile[i].first * std::cos(a), profile[i].first * std::sin(a), profile[i].second});
    }
  m.positions.push_back({0, 0, profile.back().second});
  const Index south = Index(m.positions.size() - 1);
  const auto ring = [&](int i, int j) { return Index(1 + (i - 1) * segments + (j % segments)); };
  for (int j = 0; j < segments; ++j) m.faces.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      m.faces.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.faces.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  for (int j = 0; j < segments; ++j) m.faces.push_back({south, ring(rings, j + 1), ring(rings, j)});
  return m;
}

Mesh uv_sphere(double r, int rings, int segments) {
  std::vector<std::pair<double, double>> profile;
  for (int i = 0; i <= rings; ++i) {
    const double th = std::numbers::pi * i / rings;
    profile.push_back({i == 0 || i == rings ? 0.0 : r * std::sin(th), i == 0 ? r : i == rings ? -r : r * std::cos(th)});
  }
  return revolve(profile, segments);
}

Mesh torus(double R, double r, int rings, int segments) {
  std::vector<std::pair<double, double>> circle;
  for (int j = 0; j < segments; ++j) {
    const double v = 2 * std::numbers::pi * j / segments;
    circle.push_back({R + r * std::cos(v), r * std::sin(v)});
  }
  return swept(circle, rings);
}

Mesh swept(const std::vector<std::pair<double, double>>& section, int rings) {
  Mesh m;
  const int k = int(section.size());
  for (int i = 0; i < rings; ++i)
    for (const auto& [r, z] : section) {
      const double u = 2 * std::numbers::pi * i / rings;
      m.positions.push_back({r * std::cos(u), r * std::sin(u), z});
    }
  const auto id = [&](int i, int j) { return Index((i % rings) * k + (j % k)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < k; ++j) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

Mesh grid(int n) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.push_back({double(i), double(j), 0});
  auto id = [&](int i, int j) { return Index(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

Mesh merged(const Mesh& a, const Mesh& b) {
  Mesh m = a;
  const Index off = Index(a.positions.size());
  m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
  for (Tri t : b.faces) m.faces.push_back({t[0] + off, t[1] + off, t[2] + off});
  return m;
}

fs::path sample(const std::string& file_name) {
  const fs::path p = fs::path(CGVIEW_SAMPLES_DIR) / file_name;
  EXPECT_TRUE(fs::exists(p)) << "missing sample mesh " << p << " (install libcgal-demo and re-run cmake)";
  return p;
}

std::vector<fs::path> sample_family() {
  std::vector<fs::path> out;
  for (const char* n : {"elephant.off", "camel.off", "armadillo.off", "bunny00.off", "man.off", "cube.off",
                        "sphere.off", "cube-ouvert.off", "double-torus-example.off", "colored_tetra.ply"})
    out.push_back(sample(n));
  return out;
}

fs::path temp_dir(const std::string& tag) {
  const fs::path base = fs::temp_directory_path() / ("cgview-test-" + std::to_string(::getpid()));
  const fs::path p = base / tag;
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

void write_text(const fs::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f << bytes;
}

int run(const std::string& command, std::string* output) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buf;
  std::string out;
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string bin(const std::string& name) { return std::string(CGVIEW_BIN_DIR) + "/" + name; }

namespace {
std::string varint(std::uint64_t v) {
  std::string s;
  do {
    unsigned char c = v & 0x7f;
    v >>= 7;
    if (v) c |= 0x80;
    s.push_back(char(c));
  } while (v);
  return s;
}
}  // namespace

std::string draco_claiming(std::uint64_t faces, std::uint64_t vertices) {
  std::string d = std::string("DRACO") + '\x02' + '\x02' + '\x01' + '\x01' + std::string(2, '\0');
  d += '\0';  // standard traversal
  d += varint(vertices) + varint(faces) + '\0' + varint(faces * 3 / 4) + varint(0);
  return d + std::string(8, '\0');
}

}  // namespace cgview::test
