// Shared helpers for the tests: generated shapes with known answers, sample
// meshes, temporary directories and running programs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh.h"

namespace cgview::test {

// An axis-aligned box with 8 vertices and 12 triangles, outward oriented.
Mesh box(Vec3 min = {0, 0, 0}, Vec3 max = {1, 1, 1});
// A UV sphere of radius r: `rings` bands, `segments` around; closed, genus 0.
Mesh uv_sphere(double r = 1.0, int rings = 16, int segments = 32);
// A closed surface of revolution about z from a profile (radius, z) that runs
// from the top pole to the bottom pole (radius 0 at both ends): a fan at each
// pole, two triangles per quad between rings; outward-oriented.
Mesh revolve(const std::vector<std::pair<double, double>>& profile, int segments);
// A torus (major radius R, minor radius r): closed, genus 1.
Mesh torus(double R = 2.0, double r = 0.5, int rings = 24, int segments = 12);
// A closed polygon of the (r, z) half-plane, counter-clockwise, swept about
// the z axis in `rings` steps: the ring whose cross-section it is
// (outward-oriented, genus 1).  torus() sweeps a circle.
Mesh swept(const std::vector<std::pair<double, double>>& section, int rings);
// A flat n x n grid of squares in the z = 0 plane: one boundary loop, genus 0.
Mesh grid(int n = 4);

// A Draco 2.2 edgebreaker stream whose connectivity header claims `faces`
// faces and `vertices` vertices, followed by eight zero bytes: a lie of 33
// bytes when it claims 1.4 billion.
std::string draco_claiming(std::uint64_t faces, std::uint64_t vertices = 3);

// a and b side by side as one mesh (b's indices shifted).
Mesh merged(const Mesh& a, const Mesh& b);

// The path of a sample mesh (build/samples); the test fails if it is missing.
std::filesystem::path sample(const std::string& file_name);
// A few real sample meshes of different kinds, for invariants over a family.
std::vector<std::filesystem::path> sample_family();

// A fresh empty directory under the system's temporary directory.
std::filesystem::path temp_dir(const std::string& tag);
void write_text(const std::filesystem::path& p, const std::string& bytes);

// Runs a command through the shell; returns its exit status and fills the
// combined output.
int run(const std::string& command, std::string* output = nullptr);
// build/bin/NAME
std::string bin(const std::string& name);

}  // namespace cgview::test
