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

// Calls f(line) for each line, without its end of line (as TextScanner ends lines).
template <class F>
void for_each_line(std::string_view bytes, F&& f) {
  const char eol = TextScanner::line_end_of(bytes);
  while (!bytes.empty()) {
    const std::size_t end = bytes.find(eol);
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

// A whole word as a number.
bool parse_float(std::string_view w, float& out) {
  const auto r = std::from_chars(w.data(), w.data() + w.size(), out);
  return !w.empty() && r.ec == std::errc() && r.ptr == w.data() + w.size();
}
bool is_number(std::string_view w) {
  float x;
  return parse_float(w, x);
}

// The file a texture statement names after its options ("-s 1 1 1 -clamp on
// fuze uv.jpg" -> "fuze uv.jpg"): the rest of the line, spaces included, as
// Blender, MeshLab and three.js's MTLLoader take it.  Each option's
// arguments are its numbers (-o, -s, -t: up to three; -mm: two) or one word
// (-blendu on, -imfchan r, ...).
std::string_view texture_file_name(std::string_view rest) {
  TextScanner in(rest, kLine);
  for (;;) {
    in.skip_blanks();
    const char* start = in.pos();
    const std::string_view option = in.word();
    if (option.size() < 2 || option[0] != '-' || is_number(option)) return trim({start, std::size_t(in.end() - start)});
    const std::string_view o = option.substr(1);
    const int numbers = o == "o" || o == "s" || o == "t" ? 3 : o == "mm" ? 2 : 0;
    if (numbers == 0) {
      in.word();
      continue;
    }
    for (int k = 0; k < numbers; ++k) {
      const char* before = in.pos();
      if (!is_number(in.word())) {
        in.set_pos(before);
        break;
      }
    }
  }
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
      for (std::size_t i = 0; ok && i < 3; ++i) ok = parse_float(w[i], kd[i]);
      if (ok) out.back().kd = kd;
    } else if (!out.empty() && key == "map_Kd") {
      out.back().map_kd = std::string(texture_file_name(rest));
    }
    return true;
  });
  return out;
}

ObjMaterialUse obj_material_use(std::string_view obj_bytes) {
  std::string joined;  // as read_obj reads it
  obj_bytes = detail::join_continued_lines(obj_bytes, joined);
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
