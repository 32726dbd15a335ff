// cgview: the command line.  `cgview info`, `cgview convert`, `cgview samples`.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <deque>
#include <memory>
#include <optional>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/mesh_report.h"
#include "io/mesh_formats.h"
#include "io/mesh_io.h"
#include "algorithm_json.h"
#include "io/samples.h"
#include "io/skeleton_io.h"
#include "io/zip_bundle.h"
#include "mesh_report_json.h"
#include "plugin_option.h"
#include "registry/artifact_io.h"
#include "registry/registry.h"
#include "render/renderer.h"
#include "voxel/voxel_io.h"

#include <chrono>
#include <cmath>
#include <unistd.h>

namespace {

using namespace cgview;

constexpr const char* kVersion = "0.1.0";

struct Usage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

const char* kMainHelp =
    "usage: cgview COMMAND [ARGS]\n"
    "\n"
    "CGView's command line: mesh reports and conversions, on the same library as the server.\n"
    "\n"
    "commands:\n"
    "  info MESH [--json]     counts, bounding box, topology and defects of a mesh\n"
    "  convert IN OUT         convert between formats (from the file extensions)\n"
    "  samples                list the sample meshes (usable by name: cgview info elephant)\n"
    "  list [--json]          the registered algorithms and their parameters\n"
    "  run ALGO MESH [--PARAM VALUE]... [-o OUT]\n"
    "                         run an algorithm (cgview run ALGO --help lists its parameters)\n"
    "  run --plugin FILE.cpp ALGO MESH ...\n"
    "                         build your own algorithm file (as the template) and run it\n"
    "  render MESH -o OUT.png [--mode smooth] [--size 800x600] [--views N]\n"
    "                         a picture (or a contact sheet of N views) from the EGL renderer\n"
    "\n"
    "options:\n"
    "  -h, --help             this help (also: cgview COMMAND --help)\n"
    "  --version              the version\n"
    "\n"
    "MESH is a file or the name of a sample mesh; info and convert also take a zip of\n"
    "one mesh file with its companions (an OBJ with its MTL and textures, as the server takes).\n";

const char* kInfoHelp =
    "usage: cgview info MESH [--json]\n"
    "\n"
    "Prints the report of a mesh: vertices, faces, edges, bounding box, connected\n"
    "components, boundary loops, genus, manifoldness, degenerate and duplicate faces.\n"
    "\n"
    "  --json     one JSON object (keys: vertices, faces, edges, bbox, components,\n"
    "             boundary_loops, genus, manifold, degenerate_faces, and details)\n"
    "\n"
    "MESH is a file, a zip of one mesh file with its companions (an OBJ with its MTL\n"
    "and textures, as the server takes), or the name of a sample mesh (see cgview samples).\n";

// One line a mesh format: its extensions and what of it is read.
std::string format_lines() {
  std::string s;
  for (const MeshFormatInfo& f : mesh_formats()) {
    std::string exts;
    for (const std::string& e : f.extensions) exts += (exts.empty() ? "" : " ") + e;
    s += "    " + exts + std::string(exts.size() < 10 ? 10 - exts.size() : 1, ' ') + f.help +
         (f.write ? "" : " (read only)") + "\n";
  }
  return s;
}

std::string convert_help() {
  return "usage: cgview convert IN OUT [--ascii] [--bits N] [--no-weld]\n"
         "\n"
         "Reads IN and writes OUT, each format from its extension.\n"
         "  reads:  " +
         readable_formats() +
         ", or a .zip of one mesh file with its companions (an OBJ with its MTL and textures)\n"
         "  writes: " +
         writable_formats() + "\n" + format_lines() +
         "\n"
         "  --ascii      write PLY and STL as text (default: binary)\n"
         "  --bits N     Draco position quantization in bits (default 14)\n"
         "  --no-weld    keep STL corners apart instead of merging equal ones\n";
}

const char* kSamplesHelp =
    "usage: cgview samples [--json]\n"
    "\n"
    "Lists the sample meshes (CGAL's data set from Debian's libcgal-demo) and where\n"
    "they are; any of them can be named instead of a path: cgview info elephant.\n";

bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "-h" || a == "--help") return true;
  return false;
}

std::filesystem::path need_mesh(const std::string& arg) {
  auto p = resolve_mesh_path(arg);
  if (!p) throw IoError(arg + ": no such file, and no sample mesh of that name (see cgview samples)");
  return *p;
}

// A mesh as info and convert read it: a mesh file, or a zip bundle (as the
// server takes: a mesh with its MTL and textures) unpacked into a temporary
// directory, removed once the mesh is read, the mesh read beside its files.
struct MeshInput {
  ReadResult read;
  std::string entry;  // a bundle's mesh file, as named in the zip; empty for a plain file
};

// A glTF's buffers and images named by relative URIs (ReadOptions::companion):
// files in the mesh file's directory or below it, a symbolic link out of it
// refused, all of them together at most options.max_bytes.  `held` keeps
// their bytes for the read.
ReadOptions with_companions(ReadOptions options, const std::filesystem::path& mesh, std::deque<std::string>& held) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(fs::absolute(mesh).parent_path(), ec);
  if (ec) return options;
  auto left = std::make_shared<std::uint64_t>(options.max_bytes);
  options.companion = [root, left, &held](const std::string& relative) -> std::optional<std::string_view> {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(root / fs::path(relative), ec);
    if (ec || std::mismatch(root.begin(), root.end(), p.begin(), p.end()).first != root.end() ||
        !fs::is_regular_file(p, ec))
      return std::nullopt;
    held.push_back(read_file_bytes(p, *left));
    *left -= held.back().size();
    return std::string_view(held.back());
  };
  return options;
}

MeshInput read_mesh_input(const std::filesystem::path& file, const ReadOptions& plain_options = {}) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  std::deque<std::string> held;
  if (ext != ".zip") return {read_mesh_file(file, with_companions(plain_options, file, held)), ""};
  const ReadOptions& options = plain_options;
  const BundleDir bundle(file, std::size_t(options.max_bytes));
  // Messages name the zip's entry, not the temporary directory that is gone.
  const std::string tmp = bundle.dir().string() + "/";
  const std::string shown = file.string() + ":";
  auto in_zip = [&](std::string m) {
    for (std::size_t at; (at = m.find(tmp)) != std::string::npos;) m.replace(at, tmp.size(), shown);
    return m;
  };
  ReadResult r;
  try {
    r = read_mesh_file(bundle.mesh_path(), with_companions(options, bundle.mesh_path(), held));
  } catch (const InvalidInput& e) {
    throw InvalidInput(in_zip(e.what()));
  } catch (const IoError& e) {
    throw IoError(in_zip(e.what()));
  }
  for (auto& w : r.warnings) w = in_zip(w);
  return {std::move(r), bundle.mesh_entry()};
}

void print_warnings(const ReadResult& r) {
  for (const auto& w : r.warnings) std::fprintf(stderr, "cgview: warning: %s\n", w.c_str());
}

int cmd_info(const std::vector<std::string>& args) {
  if (wants_help(args)) {
    std::fputs(kInfoHelp, stdout);
    return 0;
  }
  bool json = false;
  std::string path;
  for (const auto& a : args) {
    if (a == "--json") json = true;
    else if (a.starts_with("-")) throw Usage("info: unknown option " + a);
    else if (path.empty()) path = a;
    else throw Usage("info: one mesh at a time");
  }
  if (path.empty()) throw Usage("info: which mesh?");
  const auto file = need_mesh(path);
  const MeshInput input = read_mesh_input(file);
  const ReadResult& r = input.read;
  print_warnings(r);
  const MeshReport rep = mesh_report(r.mesh);
  if (json) {
    nlohmann::json j = protocol::to_json(rep);
    j["file"] = file.string();
    j["format"] = to_string(r.format);
    if (!input.entry.empty()) j["entry"] = input.entry;
    j["warnings"] = r.warnings;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  auto yes = [](bool b) { return b ? "yes" : "no"; };
  if (input.entry.empty()) std::printf("file              %s (%s)\n", file.c_str(), to_string(r.format));
  else std::printf("file              %s: %s (%s)\n", file.c_str(), input.entry.c_str(), to_string(r.format));
  std::printf("vertices          %llu\n", (unsigned long long)rep.vertices);
  std::printf("faces             %llu\n", (unsigned long long)rep.faces);
  if (rep.point_cloud()) std::printf("point cloud       yes (points and no faces)\n");
  std::printf("edges             %llu\n", (unsigned long long)rep.edges);
  if (!rep.bbox.empty())
    std::printf("bounding box      [%g %g %g] .. [%g %g %g] (size %g x %g x %g)\n", rep.bbox.min.x, rep.bbox.min.y,
                rep.bbox.min.z, rep.bbox.max.x, rep.bbox.max.y, rep.bbox.max.z, rep.bbox.size().x, rep.bbox.size().y,
                rep.bbox.size().z);
  std::printf("components        %llu\n", (unsigned long long)rep.components);
  std::printf("boundary loops    %llu\n", (unsigned long long)rep.boundary_loops);
  if (rep.genus) std::printf("genus             %lld\n", (long long)*rep.genus);
  else std::printf("genus             n/a (not a manifold, consistently oriented mesh)\n");
  std::printf("manifold          %s", yes(rep.manifold));
  if (!rep.manifold)
    std::printf(" (%llu non-manifold edges, %llu non-manifold vertices)", (unsigned long long)rep.non_manifold_edges,
                (unsigned long long)rep.non_manifold_vertices);
  std::printf("\nclosed            %s\n", yes(rep.closed));
  std::printf("oriented          %s\n", yes(rep.oriented));
  std::printf("degenerate faces  %llu\n", (unsigned long long)rep.degenerate_faces);
  std::printf("duplicate faces   %llu\n", (unsigned long long)rep.duplicate_faces);
  std::printf("isolated vertices %llu\n", (unsigned long long)rep.isolated_vertices);
  std::printf("area              %g\n", rep.area);
  if (rep.volume) std::printf("volume            %g\n", *rep.volume);
  return 0;
}

int cmd_convert(const std::vector<std::string>& args) {
  if (wants_help(args)) {
    std::fputs(convert_help().c_str(), stdout);
    return 0;
  }
  std::vector<std::string> paths;
  WriteOptions wo;
  ReadOptions ro;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const auto& a = args[i];
    if (a == "--ascii") wo.binary = false;
    else if (a == "--no-weld") ro.weld_stl = false;
    else if (a == "--bits") {
      if (i + 1 >= args.size()) throw Usage("convert: --bits needs a number");
      try {
        std::size_t used = 0;
        wo.position_bits = std::stoi(args[++i], &used);
        if (used != args[i].size()) throw std::invalid_argument("");
      } catch (const std::logic_error&) {
        throw Usage("convert: --bits needs a number, got '" + args[i] + "'");
      }
    } else if (a.starts_with("-")) throw Usage("convert: unknown option " + a);
    else paths.push_back(a);
  }
  if (paths.size() != 2) throw Usage("convert: needs IN and OUT");
  const MeshFormat out_format = format_from_name(paths[1]);
  if (!can_write(out_format))
    throw UnsupportedFormat(std::string("cannot write ") + to_string(out_format) + " (writable: " + writable_formats() +
                            ")");
  const auto in = need_mesh(paths[0]);
  const ReadResult r = read_mesh_input(in, ro).read;
  print_warnings(r);
  write_mesh(r.mesh, paths[1], wo);
  return 0;
}

int cmd_samples(const std::vector<std::string>& args) {
  if (wants_help(args)) {
    std::fputs(kSamplesHelp, stdout);
    return 0;
  }
  const bool json = !args.empty() && args[0] == "--json";
  const auto dir = samples_dir();
  if (!dir) throw IoError("no sample meshes found: install Debian's libcgal-demo and rebuild, or set CGVIEW_SAMPLES");
  const auto files = list_samples();
  if (json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& f : files) j.push_back({{"name", f.stem().string()}, {"path", f.string()}});
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("%zu sample meshes in %s:\n", files.size(), dir->c_str());
  for (const auto& f : files) std::printf("  %s\n", f.filename().c_str());
  return 0;
}

std::string param_line(const ParamSpec& p) {
  std::string s = "  --" + p.name + " " + to_string(p.type);
  if (s.size() < 30) s.resize(30, ' ');
  s += p.info.label + " (default " + to_string(p.default_value);
  if (p.info.min) s += ", min " + to_string(ParamValue(*p.info.min));
  if (p.info.max) s += ", max " + to_string(ParamValue(*p.info.max));
  if (!p.info.choices.empty()) {
    s += ", one of";
    for (const auto& c : p.info.choices) s += " " + c;
  }
  s += ")";
  if (!p.info.help.empty()) s += ": " + p.info.help;
  return s + "\n";
}

int cmd_list(std::vector<std::string> args) {
  cli::take_plugin_options(args);
  if (wants_help(args)) {
    std::fputs(
        "usage: cgview list [--json] [--plugin FILE.cpp]\n\nThe registered algorithms, with their parameters (--json: "
        "with JSON Schemas), and those of the plugins named.\n",
        stdout);
    return 0;
  }
  if (!args.empty() && args[0] == "--json") {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& [name, a] : algorithms()) j.push_back(protocol::to_json(a));
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  if (!args.empty()) throw Usage("list: unknown option " + args[0]);
  for (const auto& [name, a] : algorithms()) {
    std::printf("%-24s %s\n", name.c_str(), a.info.title.c_str());
    for (const auto& p : a.params) std::fputs(param_line(p).c_str(), stdout);
  }
  return 0;
}

// A progress bar on a terminal, plain lines (every 10% or new stage) otherwise.
class ProgressPrinter {
 public:
  ProgressPrinter() : tty_(::isatty(2)) {}
  ~ProgressPrinter() {
    if (tty_ && drawn_) std::fputc('\n', stderr);
  }
  void operator()(double f, std::string_view stage) {
    f = std::clamp(f, 0.0, 1.0);
    const int pct = int(std::lround(f * 100));
    if (tty_) {
      const auto now = std::chrono::steady_clock::now();
      if (pct != 100 && now - last_ < std::chrono::milliseconds(100) && stage == stage_) return;
      last_ = now;
      std::string bar(30, ' ');
      for (int i = 0; i < int(f * 30); ++i) bar[std::size_t(i)] = '=';
      std::fprintf(stderr, "\r[%s] %3d%% %-24.*s", bar.c_str(), pct, int(stage.size()), stage.data());
      drawn_ = true;
    } else if (stage != stage_ || pct / 10 != last_pct_ / 10) {
      std::fprintf(stderr, "progress %3d%% %.*s\n", pct, int(stage.size()), stage.data());
    }
    stage_ = stage;
    last_pct_ = pct;
  }

 private:
  bool tty_, drawn_ = false;
  std::string stage_;
  int last_pct_ = -100;
  std::chrono::steady_clock::time_point last_{};
};

int cmd_run(std::vector<std::string> args) {
  cli::take_plugin_options(args);
  if (args.empty() || args[0] == "-h" || args[0] == "--help") {
    std::fputs(
        "usage: cgview run ALGO MESH [--PARAM VALUE]... [-o OUT]\n\n"
        "Runs a registered algorithm on a mesh and saves its results. With several results,\n"
        "OUT names the first and the others are saved beside it as OUTSTEM-NAME.EXT.\n"
        "A scalar field saves as .txt, .csv or .ply; see cgview list for the algorithms.\n"
        "--plugin FILE.cpp builds an algorithm file of your own (see docs/TUTORIAL.md) and\n"
        "runs its algorithm as any other: cgview run --plugin height.cpp height MESH\n",
        stdout);
    return 0;
  }
  const Algorithm* algo;
  try {
    algo = &find_algorithm(args[0]);
  } catch (const std::out_of_range& e) {
    throw Usage(std::string("run: ") + e.what() + " (see cgview list)");
  }
  if (wants_help(args)) {
    std::printf("usage: cgview run %s MESH [--PARAM VALUE]... [-o OUT]\n\n%s: %s\n\nparameters:\n", args[0].c_str(),
                algo->info.title.c_str(), algo->info.description.c_str());
    for (const auto& p : algo->params) std::fputs(param_line(p).c_str(), stdout);
    if (algo->info.inputs.size() > 1) {
      std::printf("\ninputs (the first is MESH, the others --NAME FILE):\n");
      for (const auto& in : algo->info.inputs)
        std::printf("  %-20s %s (%s)\n", in.name.c_str(), in.help.c_str(), to_string(in.kind));
    }
    std::printf("\noutputs:\n");
    for (const auto& [name, kind] : algo->info.outputs) std::printf("  %s (%s)\n", name.c_str(), to_string(kind));
    return 0;
  }
  std::string mesh_arg, out;
  std::map<std::string, ParamValue> values;
  std::map<std::string, std::string> more_inputs;  // input name -> file, for all but the first
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-o" || a == "--output") {
      if (i + 1 >= args.size()) throw Usage("run: -o needs a file");
      out = args[++i];
    } else if (a.starts_with("--")) {
      const std::string name = a.substr(2);
      const bool is_input = std::any_of(algo->info.inputs.begin() + (algo->info.inputs.empty() ? 0 : 1),
                                        algo->info.inputs.end(), [&](const InputSpec& in) { return in.name == name; });
      if (is_input) {
        if (i + 1 >= args.size()) throw Usage("run: --" + name + " needs a mesh file");
        more_inputs[name] = args[++i];
        continue;
      }
      const ParamSpec* spec = nullptr;
      for (const auto& p : algo->params)
        if (p.name == name) spec = &p;
      if (!spec)
        throw Usage("run: " + args[0] + " has no parameter --" + name + " (see cgview run " + args[0] + " --help)");
      if (i + 1 >= args.size()) throw Usage("run: --" + name + " needs a value");
      const std::string& v = args[++i];
      // A selection may be long: --faces @ids.txt reads it from a file.
      values[name] = parse_param(*spec, is_selection(spec->type) && v.starts_with("@")
                                            ? read_file_bytes(v.substr(1), std::uint64_t(1) << 30)
                                            : v);
    } else if (mesh_arg.empty()) mesh_arg = a;
    else throw Usage("run: unexpected argument '" + a + "'");
  }
  if (mesh_arg.empty()) throw Usage("run: which mesh?");
  if (!out.empty() && !algo->info.outputs.empty()) check_artifact_extension(algo->info.outputs[0].second, out);
  // Each input from its file: MESH for the first, --NAME FILE for the others;
  // a voxel_grid input reads a grid file (.nrrd, .binvox, .vti, .vox, .vdb, ...),
  // a skeleton input a skeleton file (.polylines.txt, .cg, .obj, .json).
  InputFiles files;
  for (std::size_t k = 0; k < algo->info.inputs.size(); ++k) {
    const InputSpec& in = algo->info.inputs[k];
    std::string file;
    if (k == 0) {
      file = mesh_arg;
    } else {
      const auto f = more_inputs.find(in.name);
      if (f == more_inputs.end()) throw Usage("run: " + args[0] + " needs --" + in.name + " FILE (" + in.help + ")");
      file = f->second;
    }
    for (const auto& w : files.read(in, in.kind == OutputKind::mesh ? need_mesh(file) : std::filesystem::path(file)))
      std::fprintf(stderr, "cgview: warning: %s\n", w.c_str());
  }
  const Inputs& inputs = files.inputs();
  const Mesh& input_mesh = files.primary_mesh();
  ProgressPrinter printer;
  Context ctx([&](double f, std::string_view stage) { printer(f, stage); }, nullptr);
  const AlgorithmResult result = algo->run(inputs, values, ctx);
  for (const auto& w : result.warnings) std::fprintf(stderr, "cgview: warning: %s\n", w.c_str());
  for (std::size_t k = 0; k < result.artifacts.size(); ++k) {
    const Artifact& art = result.artifacts[k];
    std::filesystem::path path;
    if (out.empty()) path = std::filesystem::path(mesh_arg).stem().string() + "-" + art.name + default_extension(art);
    else if (k == 0) path = out;
    else {
      const std::filesystem::path o(out);
      path = o.parent_path() / (o.stem().string() + "-" + art.name + default_extension(art));
    }
    write_artifact(art, input_mesh, path);
    std::printf("%s: %s\n", art.name.c_str(), path.c_str());
  }
  return 0;
}

const char* kRenderHelp =
    "usage: cgview render MESH -o OUT.png [options]\n"
    "\n"
    "Renders the mesh offscreen (EGL, no window or X server: a GPU when there is one,\n"
    "else Mesa's llvmpipe) into a PNG.\n"
    "\n"
    "  -o FILE             the PNG to write (required)\n"
    "  --mode M            points, wireframe, flat, smooth (default) or toon\n"
    "  --size WxH          image size, each in [1, 8192] (default 800x600; 256x256 a view with --views)\n"
    "  --views N           a contact sheet of N views around the mesh (azimuths 360/N apart)\n"
    "  --azimuth DEG       camera azimuth around +y (default 30)\n"
    "  --elevation DEG     camera elevation in [-90, 90] (default 20)\n"
    "  --distance D        camera distance from the centre (default: fit the bounding box)\n"
    "  --ortho             orthographic projection (default perspective)\n"
    "  --silhouette        write the binary silhouette (white on black) instead of colours\n"
    "  --depth FILE        also write the depth buffer: raw float32, rows from the top, window depth\n"
    "                      in [0, 1] (1: background); not with --views\n"
    "  --face-ids FILE     also write the face seen at each pixel: raw uint32 (4294967295: none)\n"
    "  --skeleton FILE     draw a skeleton over the mesh (.polylines.txt, .cg, .obj, .json)\n"
    "  --gl-platform P     auto (default: GPU device, else surfaceless llvmpipe), device or surfaceless;\n"
    "                      also the environment variable CGVIEW_GL_PLATFORM\n";

int parse_int_option(const std::string& name, const std::string& text) {
  try {
    std::size_t used = 0;
    const int v = std::stoi(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
    return v;
  } catch (const std::logic_error&) {
    throw Usage("render: " + name + " needs an integer, got '" + text + "'");
  }
}

double parse_double_option(const std::string& name, const std::string& text) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v)) throw std::invalid_argument(text);
    return v;
  } catch (const std::logic_error&) {
    throw Usage("render: " + name + " needs a number, got '" + text + "'");
  }
}

int cmd_render(const std::vector<std::string>& args) {
  if (wants_help(args)) {
    std::fputs(kRenderHelp, stdout);
    return 0;
  }
  std::string mesh_arg, out;
  render::RenderParams params;
  bool size_given = false, silhouette = false;
  int views = 0;
  render::GlPlatform platform = render::GlPlatform::automatic;
  std::string depth_out, ids_out, skeleton_file;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw Usage("render: " + a + " needs a value");
      return args[++i];
    };
    if (a == "-o") out = value();
    else if (a == "--mode") params.mode = render::parse_render_mode(value(), "--mode");
    else if (a == "--size") {
      const std::string& v = value();
      const std::size_t x = v.find('x');
      if (x == std::string::npos) throw Usage("render: --size needs WIDTHxHEIGHT, got '" + v + "'");
      params.width = parse_int_option("--size", v.substr(0, x));
      params.height = parse_int_option("--size", v.substr(x + 1));
      size_given = true;
    } else if (a == "--views") {
      views = parse_int_option("--views", value());
      if (views < 1 || views > 1024) throw Usage("render: --views must be in [1, 1024]");
    } else if (a == "--azimuth") params.camera.azimuth = parse_double_option(a, value());
    else if (a == "--elevation") params.camera.elevation = parse_double_option(a, value());
    else if (a == "--distance") params.camera.distance = parse_double_option(a, value());
    else if (a == "--ortho") params.camera.projection = render::Projection::orthographic;
    else if (a == "--silhouette") silhouette = true;
    else if (a == "--depth") depth_out = value();
    else if (a == "--face-ids") ids_out = value();
    else if (a == "--skeleton") skeleton_file = value();
    else if (a == "--gl-platform") platform = render::parse_gl_platform(value(), "--gl-platform");
    else if (a.starts_with("-")) throw Usage("render: unknown option " + a);
    else if (mesh_arg.empty()) mesh_arg = a;
    else throw Usage("render: one mesh at a time");
  }
  if (mesh_arg.empty()) throw Usage("render: which mesh?");
  if (out.empty()) throw Usage("render: -o OUT.png is needed");
  if (views > 0 && !size_given) params.width = params.height = 256;
  if (views > 0 && (!depth_out.empty() || !ids_out.empty()))
    throw Usage("render: --depth and --face-ids write one view, not --views");
  try {
    render::check_image_size(params.width, params.height);
  } catch (const InvalidInput& e) {
    throw Usage(std::string("render: --size: ") + e.what());
  }
  const ReadResult r = read_mesh_file(need_mesh(mesh_arg));
  print_warnings(r);
  render::set_render_log([](const std::string& m) { std::fprintf(stderr, "cgview: %s\n", m.c_str()); });
  render::Renderer renderer(platform);
  params.silhouette = silhouette;
  params.color = !silhouette;
  params.depth = !depth_out.empty();
  params.face_ids = !ids_out.empty();
  auto write_raw = [](const std::string& path, const void* data, std::size_t bytes) {
    std::ofstream f(path, std::ios::binary);
    if (!f.write(static_cast<const char*>(data), std::streamsize(bytes))) throw IoError(path + ": cannot write");
  };
  const Skeleton skeleton = skeleton_file.empty() ? Skeleton{} : read_skeleton(skeleton_file);
  render::RenderItem item{&r.mesh};
  if (!skeleton_file.empty()) item.skeleton = &skeleton;
  auto picture = [&](const render::RenderParams& p) {
    render::RenderResult res = renderer.render({item}, p);
    if (!depth_out.empty()) write_raw(depth_out, res.depth.data(), res.depth.size() * sizeof(float));
    if (!ids_out.empty()) write_raw(ids_out, res.face_ids.data(), res.face_ids.size() * sizeof(std::uint32_t));
    return silhouette ? render::mask_image(res.silhouette, p.width, p.height) : std::move(res.color);
  };
  render::Image image;
  if (views > 0) {
    std::vector<render::Image> cells;
    for (int k = 0; k < views; ++k) {
      render::RenderParams p = params;
      p.camera.azimuth = params.camera.azimuth + 360.0 * k / views;
      cells.push_back(picture(p));
    }
    image = render::contact_sheet(cells);
  } else {
    image = picture(params);
  }
  const std::string png = render::encode_png(image);
  std::ofstream f(out, std::ios::binary);
  if (!f.write(png.data(), std::streamsize(png.size()))) throw IoError(out + ": cannot write");
  std::printf("%s: %dx%d, %s, %s\n", out.c_str(), image.width, image.height, to_string(params.mode),
              renderer.info().gl_renderer.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.empty()) throw Usage("a command is needed");
    const std::string cmd = args[0];
    std::vector<std::string> rest(args.begin() + 1, args.end());
    if (cmd == "-h" || cmd == "--help" || cmd == "help") {
      std::fputs(kMainHelp, stdout);
      return 0;
    }
    if (cmd == "--version") {
      std::printf("cgview %s\n", kVersion);
      return 0;
    }
    if (cmd == "info") return cmd_info(rest);
    if (cmd == "convert") return cmd_convert(rest);
    if (cmd == "samples") return cmd_samples(rest);
    if (cmd == "list") return cmd_list(rest);
    if (cmd == "run") return cmd_run(rest);
    if (cmd == "render") return cmd_render(rest);
    throw Usage("unknown command '" + cmd + "'");
  } catch (const Usage& e) {
    std::fprintf(stderr, "cgview: %s (see cgview --help)\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgview: error: %s\n", e.what());
    return 1;
  }
}
