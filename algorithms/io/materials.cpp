#include "io/materials.h"

#include <charconv>

#include "io/text_scanner.h"

namespace cgview {

namespace {

using detail::TextScanner;

// The name a TextScanner reports errors under: splitting a line into words never fails.
const std::string kLine = "line";

std::string_view trim(std::string_view s) {
  while (!s.empty() && TextScanner::is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && TextScanner::is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Calls f(line) for each line, without its end of line.
template <class F>
void for_each_line(std::string_view bytes, F&& f) {
  while (!bytes.empty()) {
    const std::size_t end = bytes.find('\n');
    const std::string_view line = bytes.substr(0, end);
    if (!f(line)) return;
    if (end == std::string_view::npos) return;
    bytes.remove_prefix(end + 1);
  }
}

// Splits "keyword rest of line" into its keyword and its trimmed rest.
std::pair<std::string_view, std::string_view> keyword(std::string_view line) {
  TextScanner in(line, kLine);
  const std::string_view key = in.word();
  return {key, trim({in.pos(), in.remaining()})};
}

// The words of one line, split as the mesh readers split them.
std::vector<std::string_view> words(std::string_view line) {
  TextScanner in(line, kLine);
  std::vector<std::string_view> out;
  for (std::string_view w = in.word(); !w.empty(); w = in.word()) out.push_back(w);
  return out;
}

std::size_t word_count(std::string_view line) {
  TextScanner in(line, kLine);
  std::size_t n = 0;
  while (!in.word().empty()) ++n;
  return n;
}

}  // namespace

std::vector<Material> parse_mtl(std::string_view bytes) {
  std::vector<Material> out;
  for_each_line(bytes, [&](std::string_view line) {
    const auto [key, rest] = keyword(line);
    if (key == "newmtl") {
      out.push_back({std::string(rest), std::nullopt, {}});
    } else if (!out.empty() && key == "Kd") {
      const auto w = words(rest);
      std::array<float, 3> kd{};
      bool ok = w.size() >= 3;
      for (std::size_t i = 0; ok && i < 3; ++i) {
        const auto r = std::from_chars(w[i].data(), w[i].data() + w[i].size(), kd[i]);
        ok = r.ec == std::errc() && r.ptr == w[i].data() + w[i].size();
      }
      if (ok) out.back().kd = kd;
    } else if (!out.empty() && key == "map_Kd") {
      // Options (-s 1 1 1, -bm 0.5, ...) come first: the file is the last word.
      const auto w = words(rest);
      if (!w.empty()) out.back().map_kd = std::string(w.back());
    }
    return true;
  });
  return out;
}

ObjMaterialUse obj_material_use(std::string_view obj_bytes) {
  ObjMaterialUse use;
  std::string current;
  constexpr std::uint32_t kUnknown = ~std::uint32_t(0);
  std::uint32_t index = kUnknown;  // of current in use.names, once a face uses it
  for_each_line(obj_bytes, [&](std::string_view line) {
    const auto [key, rest] = keyword(line);
    if (key == "f" || key == "fo") {
      // As read_obj: a polygon of n corners is n - 2 triangles; a comment ends the corners.
      const std::size_t n = word_count(rest.substr(0, rest.find('#')));
      if (n < 3) return true;
      if (index == kUnknown) {
        index = std::uint32_t(use.names.size());
        for (std::size_t k = 0; k < use.names.size(); ++k)
          if (use.names[k] == current) index = std::uint32_t(k);
        if (index == use.names.size()) use.names.push_back(current);
      }
      use.faces[current] += n - 2;
      use.face_material.insert(use.face_material.end(), n - 2, index);
    } else if (key == "mtllib") {
      for (const auto w : words(rest)) use.libraries.emplace_back(w);
    } else if (key == "usemtl") {
      current = std::string(rest);
      index = kUnknown;
    }
    return true;
  });
  return use;
}

std::string ply_texture_file(std::string_view ply_bytes) {
  std::string found;
  for_each_line(ply_bytes.substr(0, 1 << 16), [&](std::string_view line) {
    const auto [key, rest] = keyword(line);
    if (key == "end_header") return false;
    if (key == "comment") {
      const auto [what, name] = keyword(rest);
      if (what == "TextureFile" && !name.empty()) found = std::string(name);
    }
    return true;
  });
  return found;
}

std::string file_base_name(std::string_view path) {
  const std::size_t slash = path.find_last_of("/\\");
  return std::string(slash == std::string_view::npos ? path : path.substr(slash + 1));
}

std::string image_mime_type(std::string_view b) {
  if (b.size() >= 8 && b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) return "image/png";
  if (b.size() >= 3 && static_cast<unsigned char>(b[0]) == 0xFF && static_cast<unsigned char>(b[1]) == 0xD8 &&
      static_cast<unsigned char>(b[2]) == 0xFF)
    return "image/jpeg";
  return {};
}

}  // namespace cgview
