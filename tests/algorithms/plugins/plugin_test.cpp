// Plugins (plugins/plugin.h): a copy of the built-in centroid_distance as
// one file, built by the real compiler and loaded into this test, gives what
// the built-in gives; the code panel's template (docs/examples/height.cpp)
// builds without a warning; a file with an error gives the compiler's message at its
// line and column; a name CGView has is refused; and `cgview run --plugin`
// writes the same field as `cgview run` of the built-in.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "centroid_distance_plugin.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "plugins/plugin.h"
#include "registry/registry.h"
#include "test_support.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;

// The built-in centroid_distance as a plugin file registering `name`.
std::string template_as(const std::string& name, const std::string& from = "", const std::string& to = "") {
  std::string s = centroid_distance_plugin(CGVIEW_SOURCE_DIR, name);
  if (!from.empty()) s.replace(s.find(from), from.size(), to);
  return s;
}

fs::path scratch(const std::string& tag) {
  const fs::path d = fs::temp_directory_path() / ("cgview-plugin-test-" + tag + "-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

TEST(Plugin, ParsesTheCompilersDiagnostics) {
  const auto d = parse_diagnostics(
      "In file included from x.cpp:1:\n"
      "h.cpp:35:23: error: 'flot' was not declared in this scope; did you mean 'float'?\n"
      "   35 |     field = flot(1);\n"
      "h.cpp:2:1: warning: unused variable 'y' [-Wunused-variable]\n"
      "h.cpp:9:3: note: in expansion of macro\n"
      "/usr/include/x.h:1:10: fatal error: nope.h: No such file or directory\n");
  ASSERT_EQ(d.size(), 4u);
  EXPECT_EQ(d[0].file, "h.cpp");
  EXPECT_EQ(d[0].line, 35);
  EXPECT_EQ(d[0].column, 23);
  EXPECT_EQ(d[0].severity, "error");
  EXPECT_EQ(d[0].message, "'flot' was not declared in this scope; did you mean 'float'?");
  EXPECT_EQ(d[1].severity, "warning");
  EXPECT_EQ(d[2].severity, "note");
  EXPECT_EQ(d[3].severity, "fatal error");
  EXPECT_EQ(d[3].file, "/usr/include/x.h");
}

TEST(Plugin, ACopyOfTheTemplateBuildsLoadsAndGivesWhatTheBuiltInGives) {
  const fs::path dir = scratch("ok");
  write_file_bytes(dir / "copy.cpp", template_as("copy_distance"));
  const PluginBuild b = build_plugin(dir / "copy.cpp", dir / "copy.so");
  ASSERT_TRUE(b.ok) << b.output;
  EXPECT_EQ(load_plugin(dir / "copy.so"), std::vector<std::string>{"copy_distance"});
  const Mesh mesh = read_mesh(sample("elephant.off"));
  Context ctx;
  const std::map<std::string, ParamValue> params = {{"exponent", 2.0}, {"normalize", true}};
  const auto mine = find_algorithm("copy_distance").run(mesh, params, ctx);
  const auto ref = find_algorithm("centroid_distance").run(mesh, params, ctx);
  ASSERT_EQ(mine.artifacts.size(), 1u);
  EXPECT_EQ(std::get<ScalarField>(mine.artifacts[0].value).values,
            std::get<ScalarField>(ref.artifacts[0].value).values);
  // Its parameters are described as any algorithm's: a range checked from describe.
  EXPECT_THROW(find_algorithm("copy_distance").run(mesh, {{"exponent", 9.0}}, ctx), InvalidInput);
  fs::remove_all(dir);
}

// The code panel's template and the tutorial's example, one file: it builds
// and registers the name the panel gives it.
TEST(Plugin, TheTemplateOfTheCodePanelBuilds) {
  const fs::path dir = scratch("template");
  const PluginBuild b = build_plugin(fs::path(CGVIEW_SOURCE_DIR) / "docs/examples/height.cpp", dir / "height.so");
  ASSERT_TRUE(b.ok) << b.output;
  for (const auto& d : b.diagnostics) ADD_FAILURE() << "the template warns: " << d.message;
  EXPECT_EQ(load_plugin(dir / "height.so"), std::vector<std::string>{"height"});
  Context ctx;
  const auto r = find_algorithm("height").run(read_mesh(sample("elephant.off")), {}, ctx);
  ASSERT_EQ(r.artifacts.size(), 1u);
  const auto& values = std::get<ScalarField>(r.artifacts[0].value).values;
  EXPECT_EQ(*std::min_element(values.begin(), values.end()), 0.0f);  // from the lowest vertex
  fs::remove_all(dir);
}

TEST(Plugin, AnErrorComesBackAtItsLineAndAClashingNameIsRefused) {
  const fs::path dir = scratch("bad");
  const std::string src = template_as("bad_distance", "= float(", "= flot(");
  write_file_bytes(dir / "bad.cpp", src);
  const PluginBuild b = build_plugin(dir / "bad.cpp", dir / "bad.so");
  EXPECT_FALSE(b.ok);
  const std::size_t at = src.find("flot(");
  const int line = 1 + int(std::count(src.begin(), src.begin() + long(at), '\n'));
  ASSERT_FALSE(b.diagnostics.empty()) << b.output;
  EXPECT_EQ(b.diagnostics[0].file, "bad.cpp");
  EXPECT_EQ(b.diagnostics[0].line, line);
  EXPECT_EQ(b.diagnostics[0].column, int(at - src.rfind('\n', at)));
  EXPECT_NE(b.summary().find("bad.cpp:" + std::to_string(line)), std::string::npos) << b.summary();
  write_file_bytes(dir / "clash.cpp", template_as("centroid_distance"));
  ASSERT_TRUE(build_plugin(dir / "clash.cpp", dir / "clash.so").ok);
  try {
    load_plugin(dir / "clash.so");
    ADD_FAILURE() << "a clashing name was loaded";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("centroid_distance"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(Plugin, TheCommandLineBuildsAndRunsAPluginFile) {
  const fs::path dir = scratch("cli");
  write_file_bytes(dir / "cli.cpp", template_as("cli_distance"));
  const std::string cgview = std::string(CGVIEW_BIN_DIR) + "/cgview";
  const std::string env = "XDG_CACHE_HOME='" + (dir / "cache").string() + "' ";
  ASSERT_EQ(std::system((env + "'" + cgview + "' run --plugin '" + (dir / "cli.cpp").string() +
                         "' cli_distance elephant -o '" + (dir / "mine.txt").string() + "' > /dev/null 2>&1")
                            .c_str()),
            0);
  ASSERT_EQ(std::system(("'" + cgview + "' run centroid_distance elephant -o '" + (dir / "ref.txt").string() +
                         "' > /dev/null 2>&1")
                            .c_str()),
            0);
  EXPECT_EQ(read_file_bytes(dir / "mine.txt", 1 << 24), read_file_bytes(dir / "ref.txt", 1 << 24));
  // Built once: the cache holds its library.
  int libraries = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "cache")) libraries += e.path().extension() == ".so";
  EXPECT_EQ(libraries, 1);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cgview::test
