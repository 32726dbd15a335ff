// glTF 2.0 (.glb, .gltf): the checked reader.
#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <deque>
#include <map>
#include <numeric>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <unordered_map>

#include "core/errors.h"
#include "io/materials.h"
#include "io/parse_json.h"
#include "io/readers.h"

namespace cgview::detail {

// glTF 2.0, read here rather than by Draco's GltfDecoder: that one trusts the
// indices and sizes in the JSON (a corrupted .glb crashed it) and loads any
// file that a buffer's "uri" names (an upload could read files of the server).
// Every index and byte range is checked against what the file holds; buffer
// bytes come only from the GLB's BIN chunk, data: URIs, or the caller's
// companion files (ReadOptions::companion), asked for by a relative path
// only: a URI with a scheme, an absolute path or a ".." is refused.  The default
// scene's node tree is flattened with each node's transform; triangle, strip
// and fan primitives are read (POSITION, NORMAL, TEXCOORD_0, COLOR_0), Draco-
// compressed ones (KHR_draco_mesh_compression) through Draco's decoder.
// Each primitive's material gives its faces' base colour and texture.  Where
// primitives differ in attributes, normals and colours are kept only when all
// have them (each primitive keeps its material's colour), texture coordinates
// also when a textured primitive has them (the others' faces take (0, 0)).
namespace {

using Json = nlohmann::json;
using Mat4 = std::array<double, 16>;  // row-major

Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }
Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) c[i * 4 + j] += a[i * 4 + k] * b[k * 4 + j];
  return c;
}

std::uint32_t le32(std::string_view b, std::size_t at) {
  const auto* u = reinterpret_cast<const unsigned char*>(b.data() + at);
  return std::uint32_t(u[0]) | std::uint32_t(u[1]) << 8 | std::uint32_t(u[2]) << 16 | std::uint32_t(u[3]) << 24;
}

bool base64_decode(std::string_view in, std::string& out) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;
    if (c == '/' || c == '_') return 63;
    return -1;
  };
  out.clear();
  out.reserve(in.size() / 4 * 3);
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : in) {
    if (c == '=') break;
    const int v = value(c);
    if (v < 0) return false;
    acc = (acc << 6) | std::uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(char((acc >> bits) & 0xff));
    }
  }
  return true;
}

std::string base64_encode(std::string_view in) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < in.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, in.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) v = v << 8 | (k < n ? std::uint8_t(in[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out.push_back(k <= n ? digits[(v >> (18 - 6 * k)) & 63] : '=');
  }
  return out;
}

constexpr const char* kUploadTogether = "upload it together with the .gltf (zipped, or chosen together in the viewer)";

// A URI naming a file of the bundle as a relative path ('/'-separated,
// percent-decoded, "." components dropped), or nullopt with why it is
// refused: a scheme (file:, http:, a drive letter), an absolute path, a
// ".." component, a NUL.
std::optional<std::string> bundle_path(const std::string& uri, std::string& why) {
  std::string decoded;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    auto hex = [](char c) {
      return c >= '0' && c <= '9'   ? c - '0'
             : c >= 'a' && c <= 'f' ? c - 'a' + 10
             : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                    : -1;
    };
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      decoded.push_back(char(hex(uri[i + 1]) * 16 + hex(uri[i + 2])));
      i += 2;
    } else {
      decoded.push_back(uri[i]);
    }
  }
  const std::size_t colon = decoded.find(':');
  if (colon != std::string::npos && decoded.find_first_of("/\\") > colon) {
    why = "it names the scheme '" + decoded.substr(0, std::min<std::size_t>(colon, 16)) +
          ":' (only data: URIs and paths relative to the .gltf are read)";
    return std::nullopt;
  }
  if (decoded.empty() || decoded.find('\0') != std::string::npos) {
    why = "it is empty or holds a NUL";
    return std::nullopt;
  }
  if (decoded[0] == '/' || decoded[0] == '\\') {
    why = "it is an absolute path (only paths relative to the .gltf, inside its bundle, are read)";
    return std::nullopt;
  }
  std::string path;
  for (std::size_t b = 0;;) {
    const std::size_t e = decoded.find_first_of("/\\", b);
    const std::string part = decoded.substr(b, e == std::string::npos ? std::string::npos : e - b);
    if (part == "..") {
      why = "it leaves the .gltf's directory ('..'): only files beside the .gltf or below it are read";
      return std::nullopt;
    }
    if (!part.empty() && part != ".") path += (path.empty() ? "" : "/") + part;
    if (e == std::string::npos) break;
    b = e + 1;
  }
  if (path.empty()) {
    why = "it names no file";
    return std::nullopt;
  }
  return path;
}

class GltfReader {
 public:
  GltfReader(std::string_view bytes, const std::string& name, const ReadOptions& options, ReadResult& result)
      : bytes_(bytes), name_(name), options_(options), result_(result) {}

  void read(bool binary) {
    if (bytes_.starts_with("glTF")) read_container();
    else if (binary) fail("not a glTF binary file: no 'glTF' magic", 0);
    else json_ = bytes_;
    parse_json();
    read_scene();
    if (used_companions_) write_self_contained();
  }

 private:
  [[noreturn]] void fail(const std::string& problem, std::optional<std::uint64_t> offset = std::nullopt) const {
    throw ParseError(name_, problem, std::nullopt, offset);
  }

  // The GLB header and chunks: 12 bytes of header, then length-type-data chunks.
  void read_container() {
    if (bytes_.size() < 20) fail("the file ends inside the glTF binary header (truncated?)", bytes_.size());
    const std::uint32_t version = le32(bytes_, 4), length = le32(bytes_, 8);
    if (version != 2) fail("glTF binary version " + std::to_string(version) + " is not supported (only 2)", 4);
    if (length > bytes_.size())
      fail("the header says the file has " + std::to_string(length) + " bytes, but it has " +
               std::to_string(bytes_.size()) + " (truncated?)",
           8);
    if (length < 20) fail("the header's length " + std::to_string(length) + " is too small", 8);
    const std::uint32_t json_length = le32(bytes_, 12);
    if (le32(bytes_, 16) != 0x4E4F534Au) fail("the first chunk is not the JSON chunk", 16);
    if (json_length > length - 20)
      fail("the JSON chunk of " + std::to_string(json_length) + " bytes runs past the end of the file", 12);
    json_ = bytes_.substr(20, json_length);
    json_offset_ = 20;
    for (std::uint64_t at = 20 + std::uint64_t(json_length); at + 8 <= length;) {
      const std::uint32_t n = le32(bytes_, at), type = le32(bytes_, at + 4);
      if (n > length - at - 8) fail("a chunk of " + std::to_string(n) + " bytes runs past the end of the file", at);
      if (type == 0x004E4942u && !bin_) bin_ = bytes_.substr(at + 8, n);
      at += 8 + std::uint64_t(n);
    }
  }

  void parse_json() {
    // Dumping a value in an error message recurses once per level.
    if (const int depth = json_depth(json_); depth > kMaxJsonDepth)
      fail("the JSON nests arrays and objects " + std::to_string(depth) + " deep; at most " +
               std::to_string(kMaxJsonDepth) + " are read",
           json_offset_ ? std::optional<std::uint64_t>(json_offset_) : std::nullopt);
    try {
      doc_ = Json::parse(json_);
    } catch (const Json::exception& e) {
      std::string what = e.what();
      const auto col = what.find("column");
      const auto colon = col == std::string::npos ? std::string::npos : what.find(": ", col);
      if (colon != std::string::npos) what = what.substr(colon + 2);
      const auto* pe = dynamic_cast<const Json::parse_error*>(&e);
      const std::uint64_t at = pe && pe->byte > 0 ? std::min<std::uint64_t>(pe->byte - 1, json_.size()) : 0;
      if (json_offset_) fail("the JSON chunk is malformed: " + what, json_offset_ + at);
      throw ParseError(name_, "malformed JSON: " + what,
                       1 + std::uint64_t(std::count(json_.begin(), json_.begin() + std::ptrdiff_t(at), '\n')),
                       std::nullopt);
    }
    if (!doc_.is_object()) fail("the glTF JSON is not an object");
    // glTF 1.0 (2015) keeps buffers, meshes and accessors in objects by name.
    const auto asset = doc_.find("asset");
    const Json* version =
        asset != doc_.end() && asset->is_object() && asset->contains("version") ? &(*asset)["version"] : nullptr;
    const bool v1 = version ? version->is_string() && version->get_ref<const std::string&>().starts_with("1.")
                            : doc_.contains("buffers") && doc_["buffers"].is_object();
    if (v1) fail("glTF 1.0 is not supported (only glTF 2.0): convert it, e.g. with gltf-pipeline or Blender");
    buffers_ = &array(doc_, "buffers", "");
    views_ = &array(doc_, "bufferViews", "");
    accessors_ = &array(doc_, "accessors", "");
    meshes_ = &array(doc_, "meshes", "");
    nodes_ = &array(doc_, "nodes", "");
    materials_ = &array(doc_, "materials", "");
    buffer_data_.assign(buffers_->size(), std::nullopt);
    parts_.resize(meshes_->size());
  }

  // --- checked access to the JSON ---
  const Json& array(const Json& obj, const char* key, const std::string& where) const {
    static const Json empty = Json::array();
    const auto it = obj.find(key);
    if (it == obj.end()) return empty;
    if (!it->is_array()) fail(where + key + " is not an array");
    return *it;
  }
  const Json& object(const Json& arr, std::size_t i, const std::string& where) const {
    if (!arr[i].is_object()) fail(where + " is not an object");
    return arr[i];
  }
  std::optional<std::uint64_t> uint_field(const Json& obj, const char* key, const std::string& where) const {
    const auto it = obj.find(key);
    if (it == obj.end()) return std::nullopt;
    if (!it->is_number_integer() ||
        (it->is_number_integer() && !it->is_number_unsigned() && it->get<std::int64_t>() < 0))
      fail(where + "." + key + " is not a non-negative integer");
    return it->get<std::uint64_t>();
  }
  std::uint64_t need_uint(const Json& obj, const char* key, const std::string& where) const {
    const auto v = uint_field(obj, key, where);
    if (!v) fail(where + " has no " + key);
    return *v;
  }
  std::uint64_t index(const Json& v, std::size_t count, const std::string& where, const char* what) const {
    if (!v.is_number_integer() || (!v.is_number_unsigned() && v.get<std::int64_t>() < 0) ||
        v.get<std::uint64_t>() >= count)
      fail(where + " refers to " + what + " " + v.dump().substr(0, 24) + ", but there are " + std::to_string(count));
    return v.get<std::uint64_t>();
  }
  std::uint64_t index_field(const Json& obj, const char* key, std::size_t count, const std::string& where,
                            const char* what) const {
    const auto it = obj.find(key);
    if (it == obj.end()) fail(where + " has no " + key);
    return index(*it, count, where + "." + key, what);
  }

  // --- bytes ---
  std::string_view buffer(std::size_t i) {
    if (buffer_data_[i]) return *buffer_data_[i];
    const std::string where = "buffers[" + std::to_string(i) + "]";
    const Json& b = object(*buffers_, i, where);
    const std::uint64_t length = need_uint(b, "byteLength", where);
    std::string_view data;
    const auto uri = b.find("uri");
    if (uri == b.end()) {
      if (i != 0 || !bin_) fail(where + " has no uri and the file has no BIN chunk for it");
      data = *bin_;
    } else {
      if (!uri->is_string()) fail(where + ".uri is not a string");
      std::string why;
      const std::string& u = uri->get_ref<const std::string&>();
      const auto got = uri_bytes(u, why);
      if (!got) fail(where + ": " + why);
      data = *got;
      if (!u.starts_with("data:")) companion_buffers_.push_back(i);
    }
    if (data.size() < length)
      fail(where + " has " + std::to_string(data.size()) + " bytes, fewer than its byteLength " +
           std::to_string(length));
    buffer_data_[i] = data.substr(0, length);
    return *buffer_data_[i];
  }

  // The bytes a buffer's or an image's uri stands for: a data: URI decoded,
  // or a companion file the caller gives; nullopt with why not.
  std::optional<std::string_view> uri_bytes(const std::string& u, std::string& why) {
    const std::string shown = "'" + u.substr(0, 64) + (u.size() > 64 ? "...'" : "'");
    if (u.starts_with("data:")) {
      const auto comma = u.find(',');
      if (comma == std::string::npos || u.substr(0, comma).find(";base64") == std::string::npos) {
        why = "its data: URI is not base64";
        return std::nullopt;
      }
      decoded_.emplace_back();
      if (!base64_decode(std::string_view(u).substr(comma + 1), decoded_.back())) {
        why = "its data: URI is not valid base64";
        return std::nullopt;
      }
      return decoded_.back();
    }
    const auto path = bundle_path(u, why);
    if (!path) {
      why = "the uri " + shown + " is refused: " + why;
      return std::nullopt;
    }
    std::optional<std::string_view> bytes;
    if (options_.companion) bytes = options_.companion(*path);
    if (!bytes) {
      why = "the file '" + *path + "' it names is missing: " + kUploadTogether;
      return std::nullopt;
    }
    used_companions_ = true;
    return bytes;
  }

  std::string_view view(std::size_t i, std::uint64_t& stride) {
    const std::string where = "bufferViews[" + std::to_string(i) + "]";
    const Json& v = object(*views_, i, where);
    const std::string_view data = buffer(index_field(v, "buffer", buffers_->size(), where, "buffer"));
    const std::uint64_t offset = uint_field(v, "byteOffset", where).value_or(0);
    const std::uint64_t length = need_uint(v, "byteLength", where);
    if (offset > data.size() || length > data.size() - offset)
      fail(where + " covers bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) +
           " of a buffer of " + std::to_string(data.size()));
    stride = uint_field(v, "byteStride", where).value_or(0);
    if (stride != 0 && (stride < 4 || stride > 252 || stride % 4 != 0))
      fail(where + ".byteStride " + std::to_string(stride) + " is not a multiple of 4 in 4..252");
    return data.substr(offset, length);
  }

  // The values of accessor i as floats (normalized integers mapped to 0..1 or -1..1).
  std::vector<float> floats(std::size_t i, int min_components, int max_components, const std::string& use,
                            int& components) {
    const std::string where = "accessors[" + std::to_string(i) + "] (" + use + ")";
    const Json& a = object(*accessors_, i, where);
    const auto type = a.find("type");
    components = 0;
    if (type != a.end() && type->is_string()) {
      const std::string& t = type->get_ref<const std::string&>();
      components = t == "SCALAR" ? 1 : t == "VEC2" ? 2 : t == "VEC3" ? 3 : t == "VEC4" ? 4 : 0;
    }
    if (components < min_components || components > max_components)
      fail(where + " has type " + (type == a.end() ? std::string("(none)") : type->dump().substr(0, 16)) +
           ", expected " + (min_components == max_components ? "" : "VEC" + std::to_string(min_components) + " to ") +
           (max_components == 1 ? std::string("SCALAR") : "VEC" + std::to_string(max_components)));
    const std::uint64_t ct = need_uint(a, "componentType", where);
    const int size = ct == 5120 || ct == 5121 ? 1 : ct == 5122 || ct == 5123 ? 2 : ct == 5125 || ct == 5126 ? 4 : 0;
    if (size == 0) fail(where + ": unknown componentType " + std::to_string(ct));
    bool normalized = false;
    if (const auto n = a.find("normalized"); n != a.end()) {
      if (!n->is_boolean()) fail(where + ".normalized is not a boolean");
      normalized = n->get<bool>();
    }
    const std::uint64_t count = need_uint(a, "count", where);
    const std::uint64_t element = std::uint64_t(components) * std::uint64_t(size);
    const auto sparse = a.find("sparse");
    if (!a.contains("bufferView") && sparse == a.end()) fail(where + " has no bufferView");
    std::vector<float> out;
    if (a.contains("bufferView")) {
      const std::uint64_t offset = uint_field(a, "byteOffset", where).value_or(0);
      std::uint64_t stride = 0;
      const std::string_view data = view(index_field(a, "bufferView", views_->size(), where, "bufferView"), stride);
      if (stride == 0) stride = element;
      if (count == 0 || count > data.size() || offset > data.size() ||
          (count - 1) * stride + element > data.size() - offset)
        fail(where + ": " + std::to_string(count) + " elements of " + std::to_string(element) + " bytes from byte " +
             std::to_string(offset) + " do not fit in its bufferView of " + std::to_string(data.size()) + " bytes");
      out.resize(static_cast<std::size_t>(count * std::uint64_t(components)));
      for (std::uint64_t k = 0; k < count; ++k)
        for (int c = 0; c < components; ++c) {
          const char* p = data.data() + offset + k * stride + std::uint64_t(c * size);
          out[std::size_t(k) * std::size_t(components) + std::size_t(c)] = component(p, ct, normalized);
        }
    } else {
      // No bufferView: zeros, then the sparse values.  The zeros cost memory
      // the file does not back, so their count is bounded by the bytes the
      // file holds at all (a few bytes of JSON must not claim a billion).
      if (count == 0 || count > bytes_.size())
        fail(where + ": a count of " + std::to_string(count) + " elements, more than the file's " +
             std::to_string(bytes_.size()) + " bytes can describe");
      out.assign(static_cast<std::size_t>(count * std::uint64_t(components)), 0.f);
    }
    if (sparse != a.end()) apply_sparse(*sparse, where + ".sparse", count, components, ct, size, normalized, out);
    return out;
  }

  // A sparse accessor's substitutions: `count` element indices (strictly
  // increasing, as the glTF specification requires) and their values, each
  // replacing that element of out.
  void apply_sparse(const Json& s, const std::string& where, std::uint64_t elements, int components, std::uint64_t ct,
                    int size, bool normalized, std::vector<float>& out) {
    if (!s.is_object()) fail(where + " is not an object");
    const std::uint64_t n = need_uint(s, "count", where);
    const auto idx = s.find("indices"), val = s.find("values");
    if (idx == s.end() || !idx->is_object()) fail(where + " has no indices object");
    if (val == s.end() || !val->is_object()) fail(where + " has no values object");
    const std::uint64_t ict = need_uint(*idx, "componentType", where + ".indices");
    const std::uint64_t isize = ict == 5121 ? 1 : ict == 5123 ? 2 : ict == 5125 ? 4 : 0;
    if (isize == 0)
      fail(where + ".indices: componentType " + std::to_string(ict) + " is not an unsigned byte, short or int");
    std::uint64_t stride = 0;
    const std::string_view ib =
        view(index_field(*idx, "bufferView", views_->size(), where + ".indices", "bufferView"), stride);
    const std::uint64_t ioff = uint_field(*idx, "byteOffset", where + ".indices").value_or(0);
    const std::string_view vb =
        view(index_field(*val, "bufferView", views_->size(), where + ".values", "bufferView"), stride);
    const std::uint64_t voff = uint_field(*val, "byteOffset", where + ".values").value_or(0);
    const std::uint64_t element = std::uint64_t(components) * std::uint64_t(size);
    if (n == 0 || n > elements || ioff > ib.size() || n > (ib.size() - ioff) / isize || voff > vb.size() ||
        n > (vb.size() - voff) / element)
      fail(where + ": " + std::to_string(n) + " substitutions do not fit in their bufferViews (or exceed the " +
           std::to_string(elements) + " elements)");
    std::uint64_t last = 0;
    for (std::uint64_t k = 0; k < n; ++k) {
      unsigned char b[4] = {0, 0, 0, 0};
      std::memcpy(b, ib.data() + ioff + k * isize, std::size_t(isize));
      const std::uint64_t e =
          std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
      if (e >= elements || (k > 0 && e <= last))
        fail(
            where + ": index " + std::to_string(k) + " is " + std::to_string(e) +
            (e >= elements ? ", past the " + std::to_string(elements) + " elements" : ", not after the one before it"));
      last = e;
      for (int c = 0; c < components; ++c)
        out[std::size_t(e) * std::size_t(components) + std::size_t(c)] =
            component(vb.data() + voff + k * element + std::uint64_t(c * size), ct, normalized);
    }
  }

  static float component(const char* p, std::uint64_t ct, bool normalized) {
    unsigned char b[4] = {0, 0, 0, 0};
    std::memcpy(b, p, ct == 5120 || ct == 5121 ? 1 : ct == 5122 || ct == 5123 ? 2 : 4);
    const std::uint32_t u =
        std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
    switch (ct) {
      case 5120:
        return normalized ? std::max(float(std::int8_t(u)) / 127.f, -1.f) : float(std::int8_t(u));
      case 5121:
        return normalized ? float(u) / 255.f : float(u);
      case 5122:
        return normalized ? std::max(float(std::int16_t(u)) / 32767.f, -1.f) : float(std::int16_t(u));
      case 5123:
        return normalized ? float(u) / 65535.f : float(u);
      case 5125:
        return float(u);
      default: {
        float f;
        std::memcpy(&f, &u, 4);
        return f;
      }
    }
  }

  std::vector<std::uint32_t> indices(std::size_t i, std::uint64_t vertex_count, const std::string& use) {
    const std::string where = "accessors[" + std::to_string(i) + "] (" + use + ")";
    const Json& a = object(*accessors_, i, where);
    const std::uint64_t ct = need_uint(a, "componentType", where);
    if (ct != 5121 && ct != 5123 && ct != 5125)
      fail(where + ": indices must be unsigned byte, short or int, not componentType " + std::to_string(ct));
    // Read as raw integers (floats would round indices over 2^24).
    if (a.contains("sparse")) fail(where + ": sparse accessors are not supported");
    const auto type = a.find("type");
    if (type == a.end() || *type != "SCALAR") fail(where + " is not of type SCALAR");
    const std::uint64_t count = need_uint(a, "count", where);
    const std::uint64_t offset = uint_field(a, "byteOffset", where).value_or(0);
    std::uint64_t stride = 0;
    const std::string_view data = view(index_field(a, "bufferView", views_->size(), where, "bufferView"), stride);
    const std::uint64_t size = ct == 5121 ? 1 : ct == 5123 ? 2 : 4;
    if (stride == 0) stride = size;
    if (count == 0 || count > data.size() || offset > data.size() || (count - 1) * stride + size > data.size() - offset)
      fail(where + ": " + std::to_string(count) + " indices from byte " + std::to_string(offset) +
           " do not fit in its bufferView of " + std::to_string(data.size()) + " bytes");
    std::vector<std::uint32_t> out(static_cast<std::size_t>(count));
    for (std::uint64_t k = 0; k < count; ++k) {
      unsigned char b[4] = {0, 0, 0, 0};
      std::memcpy(b, data.data() + offset + k * stride, std::size_t(size));
      out[k] = std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
      if (out[k] >= vertex_count)
        fail(use + ": index " + std::to_string(k) + " is " + std::to_string(out[k]) + ", but there are " +
             std::to_string(vertex_count) + " vertices");
    }
    return out;
  }

  // --- geometry ---
  struct Part {
    std::vector<float> positions, normals, uvs, colors;  // 3, 3, 2 and 4 floats a vertex
    int color_components = 4;
    std::vector<std::uint32_t> corners;  // triangle corners
    std::size_t vertices = 0;
    std::int64_t material = -1;  // the primitive's glTF material, -1 for none
  };

  Part plain_primitive(const Json& prim, const std::string& where) {
    Part part;
    const auto attrs = prim.find("attributes");
    if (attrs == prim.end() || !attrs->is_object()) fail(where + " has no attributes object");
    const auto pos = attrs->find("POSITION");
    if (pos == attrs->end()) fail(where + " has no POSITION attribute");
    int comps = 0;
    part.positions = floats(index(*pos, accessors_->size(), where + ".attributes.POSITION", "accessor"), 3, 3,
                            where + " POSITION", comps);
    part.vertices = part.positions.size() / 3;
    auto optional_attr = [&](const char* key, int lo, int hi, std::vector<float>& out, int* used_comps) {
      const auto it = attrs->find(key);
      if (it == attrs->end()) return;
      int c = 0;
      out = floats(index(*it, accessors_->size(), where + ".attributes." + key, "accessor"), lo, hi, where + " " + key,
                   c);
      if (out.size() / std::size_t(c) != part.vertices)
        fail(where + ": " + key + " has " + std::to_string(out.size() / std::size_t(c)) + " values for " +
             std::to_string(part.vertices) + " positions");
      if (used_comps) *used_comps = c;
    };
    optional_attr("NORMAL", 3, 3, part.normals, nullptr);
    optional_attr("TEXCOORD_0", 2, 2, part.uvs, nullptr);
    optional_attr("COLOR_0", 3, 4, part.colors, &part.color_components);
    if (const auto ind = prim.find("indices"); ind != prim.end()) {
      part.corners =
          indices(index(*ind, accessors_->size(), where + ".indices", "accessor"), part.vertices, where + " indices");
    } else {
      part.corners.resize(part.vertices);
      for (std::size_t k = 0; k < part.vertices; ++k) part.corners[k] = std::uint32_t(k);
    }
    return part;
  }

  Part draco_primitive(const Json& ext, const std::string& where) {
    if (!ext.is_object()) fail(where + " is not an object");
    std::uint64_t stride = 0;
    const std::string_view data = view(index_field(ext, "bufferView", views_->size(), where, "bufferView"), stride);
    const auto attrs = ext.find("attributes");
    if (attrs == ext.end() || !attrs->is_object()) fail(where + " has no attributes object");
    check_draco_counts(data, name_ + " (" + where + ")");
    draco::DecoderBuffer buffer;
    buffer.Init(data.data(), data.size());
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) fail(where + ": the Draco data does not decode: " + decoded.status().error_msg_string());
    const draco::Mesh& dm = *decoded.value();
    Part part;
    part.vertices = dm.num_points();
    auto values = [&](const char* key, int comps, std::vector<float>& out,
                      bool required) -> const draco::PointAttribute* {
      const auto it = attrs->find(key);
      if (it == attrs->end()) {
        if (required) fail(where + " has no " + key + " attribute");
        return nullptr;
      }
      if (!it->is_number_integer()) fail(where + ".attributes." + key + " is not an integer");
      const draco::PointAttribute* a =
          numeric_draco_attribute(dm.GetAttributeByUniqueId(it->get<std::uint32_t>()), name_, key);
      if (!a) fail(where + ": the Draco data has no attribute " + it->dump().substr(0, 16) + " for " + key);
      out.assign(part.vertices * std::size_t(comps), 0.f);
      if (comps == 4)
        for (std::size_t k = 3; k < out.size(); k += 4) out[k] = 1.f;
      for (std::size_t k = 0; k < part.vertices; ++k) {
        const draco::PointIndex p(static_cast<draco::PointIndex::ValueType>(k));
        a->ConvertValue<float>(a->mapped_index(p), std::int8_t(std::min<int>(comps, a->num_components())),
                               out.data() + k * std::size_t(comps));
      }
      return a;
    };
    values("POSITION", 3, part.positions, true);
    values("NORMAL", 3, part.normals, false);
    values("TEXCOORD_0", 2, part.uvs, false);
    if (const draco::PointAttribute* c = values("COLOR_0", 4, part.colors, false)) {
      part.color_components = std::min<int>(4, c->num_components());
      if (!c->normalized() && c->data_type() != draco::DT_FLOAT32)  // raw bytes 0..255
        for (float& x : part.colors) x /= 255.f;
    }
    part.corners.reserve(dm.num_faces() * 3);
    for (draco::FaceIndex f(0); f < dm.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = dm.face(f)[k].value();
        if (v >= part.vertices) fail(where + ": the Draco data has a face outside its points");
        part.corners.push_back(v);
      }
    return part;
  }

  // The primitives of mesh m, read once however often nodes show the mesh.
  const std::vector<Part>& parts(std::size_t m) {
    if (parts_[m]) return *parts_[m];
    const std::string where = "meshes[" + std::to_string(m) + "]";
    const Json& mesh = object(*meshes_, m, where);
    const Json& prims = array(mesh, "primitives", where + ".");
    std::vector<Part> out;
    for (std::size_t p = 0; p < prims.size(); ++p) {
      const std::string pw = where + ".primitives[" + std::to_string(p) + "]";
      const Json& prim = object(prims, p, pw);
      const std::uint64_t mode = uint_field(prim, "mode", pw).value_or(4);
      if (mode < 4 || mode > 6) {
        ++skipped_primitives_;
        continue;
      }
      const auto ext = prim.find("extensions");
      const Json* draco_ext = nullptr;
      if (ext != prim.end() && ext->is_object()) {
        const auto d = ext->find("KHR_draco_mesh_compression");
        if (d != ext->end()) draco_ext = &*d;
      }
      Part part = draco_ext ? draco_primitive(*draco_ext, pw + ".extensions.KHR_draco_mesh_compression")
                            : plain_primitive(prim, pw);
      if (const auto mat = prim.find("material"); mat != prim.end())
        part.material = std::int64_t(index(*mat, materials_->size(), pw + ".material", "material"));
      // Triangles of the primitive's mode.
      if (mode != 4) {
        std::vector<std::uint32_t> tris;
        const std::vector<std::uint32_t>& c = part.corners;
        for (std::size_t i = 0; i + 2 < c.size(); ++i) {
          if (mode == 5) {  // strip: every other triangle flips
            if (i % 2 == 0) tris.insert(tris.end(), {c[i], c[i + 1], c[i + 2]});
            else tris.insert(tris.end(), {c[i + 1], c[i], c[i + 2]});
          } else {  // fan
            tris.insert(tris.end(), {c[0], c[i + 1], c[i + 2]});
          }
        }
        part.corners = std::move(tris);
      }
      part.corners.resize(part.corners.size() / 3 * 3);
      stored_ += part.vertices + part.corners.size();
      out.push_back(std::move(part));
    }
    parts_[m] = std::move(out);
    return *parts_[m];
  }

  void add_mesh(std::size_t m, const Mat4& matrix) {
    const bool again = parts_[m].has_value();
    for (const Part& part : parts(m)) {
      // Instancing may show more than the file stores, but not without bound.
      const std::uint64_t units = part.vertices + part.corners.size();
      used_ += units;
      if (again) repeated_ += units;
      if (repeated_ > 8 * stored_ + (1u << 20) || used_ > UINT32_MAX - 1)
        fail("the scene instantiates its meshes into over " + std::to_string(used_) +
             " vertices and corners, far more than the file stores (" + std::to_string(stored_) + "); refused");
      append(part, matrix);
    }
  }

  void append(const Part& part, const Mat4& m) {
    const std::vector<std::uint32_t>& tris = part.corners;

    Mesh& mesh = result_.mesh;
    const Index base = Index(mesh.positions.size());
    // Normals go through the cofactor matrix (the inverse transpose up to scale).
    const double a = m[0], b = m[1], cc = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], k = m[10];
    const double det = a * (e * k - f * h) - b * (d * k - f * g) + cc * (d * h - e * g);
    const double s = det < 0 ? -1.0 : 1.0;
    const double cof[9] = {s * (e * k - f * h),  s * (f * g - d * k),  s * (d * h - e * g),
                           s * (cc * h - b * k), s * (a * k - cc * g), s * (b * g - a * h),
                           s * (b * f - cc * e), s * (cc * d - a * f), s * (a * e - b * d)};
    for (std::size_t v = 0; v < part.vertices; ++v) {
      const float* p = &part.positions[v * 3];
      mesh.positions.push_back({m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3],
                                m[4] * p[0] + m[5] * p[1] + m[6] * p[2] + m[7],
                                m[8] * p[0] + m[9] * p[1] + m[10] * p[2] + m[11]});
      if (!part.normals.empty()) {
        const float* n = &part.normals[v * 3];
        const Vec3 t{cof[0] * n[0] + cof[1] * n[1] + cof[2] * n[2], cof[3] * n[0] + cof[4] * n[1] + cof[5] * n[2],
                     cof[6] * n[0] + cof[7] * n[1] + cof[8] * n[2]};
        normals_.push_back(to_float(normalized(t)));
      } else {
        normals_.push_back({});
      }
      uvs_.push_back(part.uvs.empty() ? Vec2f{} : Vec2f{part.uvs[v * 2], 1.f - part.uvs[v * 2 + 1]});
      if (!part.colors.empty()) {
        const int n = part.color_components;
        const float* q = &part.colors[v * std::size_t(part.colors.size() / part.vertices)];
        auto byte = [](float x) { return std::uint8_t(std::clamp(std::lround(x * 255.f), 0L, 255L)); };
        colors_.push_back({byte(q[0]), byte(q[1]), byte(q[2]), n >= 4 ? byte(q[3]) : std::uint8_t(255)});
      } else {
        colors_.push_back({});
      }
    }
    (part.normals.empty() ? any_without_normals_ : any_normals_) = true;
    (part.uvs.empty() ? any_without_uvs_ : any_uvs_) = true;
    (part.colors.empty() ? any_without_colors_ : any_colors_) = true;
    const std::uint32_t material = material_of(part.material);
    if (result_.materials[material].texture) ++(part.uvs.empty() ? textured_without_uvs_ : textured_with_uvs_);
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
      result_.face_material.push_back(material);
      if (det < 0) mesh.faces.push_back({base + tris[t], base + tris[t + 2], base + tris[t + 1]});
      else mesh.faces.push_back({base + tris[t], base + tris[t + 1], base + tris[t + 2]});
    }
  }

  // The index into result_.materials of glTF material m (-1: none), read on
  // first use.  A texture that cannot be shown is a warning, not a refusal.
  std::uint32_t material_of(std::int64_t m) {
    const auto [it, fresh] = material_index_.try_emplace(m, std::uint32_t(result_.materials.size()));
    if (!fresh) return it->second;
    MeshMaterial out;
    out.name = m < 0 ? "(no material)" : "material " + std::to_string(m);
    if (m >= 0) {
      const std::string where = "materials[" + std::to_string(m) + "]";
      const Json& mat = object(*materials_, std::size_t(m), where);
      if (const auto n = mat.find("name");
          n != mat.end() && n->is_string() && !n->get_ref<const std::string&>().empty())
        out.name = n->get_ref<const std::string&>().substr(0, 200);
      const auto pbr = mat.find("pbrMetallicRoughness");
      if (pbr != mat.end() && pbr->is_object()) {
        const std::string pw = where + ".pbrMetallicRoughness";
        if (const auto f = pbr->find("baseColorFactor"); f != pbr->end()) {
          if (!f->is_array() || f->size() != 4 ||
              !std::all_of(f->begin(), f->end(), [](const Json& x) { return x.is_number(); }))
            fail(pw + ".baseColorFactor is not an array of 4 numbers");
          std::array<float, 3> kd;
          for (std::size_t k = 0; k < 3; ++k) kd[k] = std::clamp((*f)[k].get<float>(), 0.f, 1.f);
          out.kd = kd;
        }
        if (const auto t = pbr->find("baseColorTexture"); t != pbr->end())
          out.texture = texture(*t, pw + ".baseColorTexture", out.name);
      }
    }
    result_.materials.push_back(std::move(out));
    return it->second;
  }

  std::optional<std::size_t> texture(const Json& info, const std::string& where, const std::string& material) {
    const std::string of = " of the material '" + material + "'";
    try {
      if (!info.is_object()) fail(where + " is not an object");
      const Json& textures = array(doc_, "textures", "");
      const std::uint64_t t = index_field(info, "index", textures.size(), where, "texture");
      if (const std::uint64_t set = uint_field(info, "texCoord", where).value_or(0); set != 0) {
        result_.warnings.push_back("the texture" + of + " uses texture coordinates TEXCOORD_" + std::to_string(set) +
                                   ", which are not read: its faces show untextured");
        return std::nullopt;
      }
      const std::string tw = "textures[" + std::to_string(t) + "]";
      const Json& tex = object(textures, t, tw);
      const auto src = tex.find("source");
      if (src == tex.end()) {
        const auto ext = tex.find("extensions");
        const std::string kind = ext != tex.end() && ext->is_object() && !ext->empty() ? ext->begin().key() : "";
        result_.warnings.push_back(
            "the texture" + of + " (" + tw + ") has no PNG or JPEG image" +
            (kind.empty() ? "" : ", only an image of " + kind.substr(0, 64) + " (KTX2 and WebP are not shown)") +
            ": its faces show untextured");
        return std::nullopt;
      }
      const Json& images = array(doc_, "images", "");
      const std::uint64_t j = index(*src, images.size(), tw + ".source", "image");
      if (const auto done = image_texture_.find(j); done != image_texture_.end()) return done->second;
      const std::optional<std::size_t> got = image(images, j, of);
      image_texture_[j] = got;
      return got;
    } catch (const ParseError& e) {
      result_.warnings.push_back(std::string(e.what()) + ": the texture" + of + " is not shown");
      return std::nullopt;
    }
  }

  std::optional<std::size_t> image(const Json& images, std::uint64_t j, const std::string& of) {
    const std::string iw = "images[" + std::to_string(j) + "]";
    const Json& img = object(images, j, iw);
    std::string label, why, declared;
    if (const auto m = img.find("mimeType"); m != img.end() && m->is_string())
      declared = m->get_ref<const std::string&>().substr(0, 64);
    std::optional<std::string_view> bytes;
    bool companion = false;
    if (const auto u = img.find("uri"); u != img.end()) {
      if (!u->is_string()) fail(iw + ".uri is not a string");
      const std::string& us = u->get_ref<const std::string&>();
      bytes = uri_bytes(us, why);
      std::string unused;
      if (!us.starts_with("data:"))
        if (const auto p = bundle_path(us, unused)) label = file_base_name(*p), companion = true;
    } else {
      std::uint64_t stride = 0;
      bytes = view(index_field(img, "bufferView", views_->size(), iw, "bufferView"), stride);
    }
    const std::string type = bytes ? image_mime_type(*bytes) : "";
    if (label.empty())
      label = "image" + std::to_string(j) + (type == "image/jpeg" ? ".jpg" : type == "image/png" ? ".png" : "");
    if (!bytes) {
      result_.warnings.push_back("the texture '" + label + "'" + of + " is not shown: " + why);
      return std::nullopt;
    }
    if (type.empty()) {
      result_.warnings.push_back("the texture '" + label + "'" + of + " is " +
                                 (declared.empty() || declared == "image/png" || declared == "image/jpeg"
                                      ? std::string("not a PNG or JPEG image")
                                      : "an " + declared + " image, not PNG or JPEG") +
                                 ": its faces show untextured");
      return std::nullopt;
    }
    if (companion) companion_images_.push_back({j, *bytes, type});
    result_.textures.push_back({label, std::string(*bytes)});
    return result_.textures.size() - 1;
  }

  // The glTF with the buffers and images read from companion files as data:
  // URIs (a GLB keeps its BIN chunk), so that it reads without them.
  void write_self_contained() {
    Json doc = doc_;
    for (const std::size_t i : companion_buffers_)
      doc["buffers"][i]["uri"] = "data:application/octet-stream;base64," + base64_encode(*buffer_data_[i]);
    for (const auto& im : companion_images_)
      doc["images"][im.index]["uri"] = "data:" + im.mime + ";base64," + base64_encode(im.bytes);
    std::string json = doc.dump();
    if (!json_offset_) {
      result_.self_contained = std::move(json);
      return;
    }
    while (json.size() % 4) json.push_back(' ');
    std::string bin = bin_ ? std::string(*bin_) : std::string();
    while (bin.size() % 4) bin.push_back('\0');
    auto put32 = [](std::string& out, std::uint64_t v) {
      for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8 * k)) & 0xff));
    };
    std::string& out = result_.self_contained;
    put32(out, 0x46546C67u);  // "glTF"
    put32(out, 2);
    put32(out, 12 + 8 + json.size() + (bin_ ? 8 + bin.size() : 0));
    put32(out, json.size());
    put32(out, 0x4E4F534Au);
    out += json;
    if (bin_) {
      put32(out, bin.size());
      put32(out, 0x004E4942u);
      out += bin;
    }
  }

  Mat4 local_matrix(const Json& node, const std::string& where) const {
    auto numbers = [&](const char* key, std::size_t n, std::vector<double>& out) {
      const auto it = node.find(key);
      if (it == node.end()) return false;
      if (!it->is_array() || it->size() != n)
        fail(where + "." + key + " is not an array of " + std::to_string(n) + " numbers");
      out.clear();
      for (const Json& x : *it) {
        if (!x.is_number()) fail(where + "." + key + " is not an array of " + std::to_string(n) + " numbers");
        out.push_back(x.get<double>());
      }
      return true;
    };
    std::vector<double> v;
    if (numbers("matrix", 16, v)) {  // column-major
      Mat4 m;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) m[i * 4 + j] = v[std::size_t(j * 4 + i)];
      return m;
    }
    Mat4 t = identity(), r = identity(), s = identity();
    if (numbers("translation", 3, v)) t[3] = v[0], t[7] = v[1], t[11] = v[2];
    if (numbers("rotation", 4, v)) {
      const double x = v[0], y = v[1], z = v[2], w = v[3];
      r = {1 - 2 * (y * y + z * z),
           2 * (x * y - z * w),
           2 * (x * z + y * w),
           0,
           2 * (x * y + z * w),
           1 - 2 * (x * x + z * z),
           2 * (y * z - x * w),
           0,
           2 * (x * z - y * w),
           2 * (y * z + x * w),
           1 - 2 * (x * x + y * y),
           0,
           0,
           0,
           0,
           1};
    }
    if (numbers("scale", 3, v)) s[0] = v[0], s[5] = v[1], s[10] = v[2];
    return mul(t, mul(r, s));
  }

  void read_scene() {
    const Json& nodes = *nodes_;
    // Each node has at most one parent (the glTF rule that makes it a tree).
    std::vector<std::uint8_t> is_child(nodes.size(), 0);
    for (std::size_t n = 0; n < nodes.size(); ++n) {
      const std::string where = "nodes[" + std::to_string(n) + "]";
      const Json& node = object(nodes, n, where);
      const Json& children = array(node, "children", where + ".");
      for (std::size_t c = 0; c < children.size(); ++c) {
        const std::uint64_t child =
            index(children[c], nodes.size(), where + ".children[" + std::to_string(c) + "]", "node");
        if (is_child[child]) fail("node " + std::to_string(child) + " is the child of more than one node");
        is_child[child] = 1;
      }
    }
    std::vector<std::uint64_t> roots;
    const Json& scenes = array(doc_, "scenes", "");
    if (!scenes.empty()) {
      std::uint64_t sc = 0;
      if (doc_.contains("scene")) sc = index(doc_["scene"], scenes.size(), "scene", "scene");
      const std::string where = "scenes[" + std::to_string(sc) + "]";
      const Json& list = array(object(scenes, sc, where), "nodes", where + ".");
      for (std::size_t i = 0; i < list.size(); ++i)
        roots.push_back(index(list[i], nodes.size(), where + ".nodes[" + std::to_string(i) + "]", "node"));
    } else {
      for (std::size_t n = 0; n < nodes.size(); ++n)
        if (!is_child[n]) roots.push_back(n);
    }
    if (nodes.empty() && scenes.empty()) {  // bare meshes, no scene
      for (std::size_t m = 0; m < meshes_->size(); ++m) add_mesh(m, identity());
    }
    std::vector<std::uint8_t> visited(nodes.size(), 0);
    std::vector<std::pair<std::uint64_t, Mat4>> stack;
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.push_back({*r, identity()});
    while (!stack.empty()) {
      const auto [n, parent] = stack.back();
      stack.pop_back();
      if (visited[n]) fail("node " + std::to_string(n) + " is reached twice (a cycle, or listed twice in the scene)");
      visited[n] = 1;
      const std::string where = "nodes[" + std::to_string(n) + "]";
      const Json& node = nodes[n];
      const Mat4 m = mul(parent, local_matrix(node, where));
      if (node.contains("mesh")) add_mesh(index(node["mesh"], meshes_->size(), where + ".mesh", "mesh"), m);
      const Json& children = array(node, "children", where + ".");
      for (std::size_t c = children.size(); c-- > 0;) stack.push_back({children[c].get<std::uint64_t>(), m});
    }

    Mesh& mesh = result_.mesh;
    if (mesh.faces.empty()) fail("the glTF scene has no triangles");
    if (any_normals_ && !any_without_normals_) mesh.normals = std::move(normals_);
    else if (any_normals_) result_.warnings.push_back("normals dropped: some primitives have them and others do not");
    if (any_uvs_ && !any_without_uvs_) {
      mesh.uvs = std::move(uvs_);
    } else if (any_uvs_ && textured_with_uvs_) {
      // A texture shows on its primitives' coordinates; the faces of
      // primitives without any take (0, 0), which their untextured
      // materials never sample.
      mesh.uvs = std::move(uvs_);
      if (textured_without_uvs_)
        result_.warnings.push_back("texture coordinates missing on " + std::to_string(textured_without_uvs_) +
                                   " textured primitive(s): their faces show one texel of the texture");
    } else if (any_uvs_) {
      result_.warnings.push_back("texture coordinates dropped: some primitives have them and others do not");
    }
    if (any_colors_ && !any_without_colors_) mesh.colors = std::move(colors_);
    else if (any_colors_)
      result_.warnings.push_back("vertex colours dropped: some primitives have them and others do not");
    if (skipped_primitives_)
      result_.warnings.push_back(std::to_string(skipped_primitives_) + " point or line primitives were skipped");
  }

  std::string_view bytes_;
  const std::string& name_;
  const ReadOptions& options_;
  ReadResult& result_;
  std::string_view json_;
  std::uint64_t json_offset_ = 0;
  std::optional<std::string_view> bin_;
  Json doc_;
  const Json* buffers_ = nullptr;
  const Json* views_ = nullptr;
  const Json* accessors_ = nullptr;
  const Json* meshes_ = nullptr;
  const Json* nodes_ = nullptr;
  const Json* materials_ = nullptr;
  struct CompanionImage {
    std::uint64_t index;
    std::string_view bytes;
    std::string mime;
  };
  bool used_companions_ = false;
  std::vector<std::size_t> companion_buffers_;  // buffers read from companion files
  std::vector<CompanionImage> companion_images_;
  std::map<std::int64_t, std::uint32_t> material_index_;               // glTF material -> result_.materials
  std::map<std::uint64_t, std::optional<std::size_t>> image_texture_;  // image -> result_.textures
  std::vector<std::optional<std::string_view>> buffer_data_;
  std::deque<std::string> decoded_;                      // data: URIs, decoded (stable addresses)
  std::vector<std::optional<std::vector<Part>>> parts_;  // per mesh, once read
  std::uint64_t stored_ = 0, used_ = 0, repeated_ = 0, skipped_primitives_ = 0;
  std::uint64_t textured_with_uvs_ = 0, textured_without_uvs_ = 0;  // primitives shown with a textured material
  std::vector<Vec3f> normals_;
  std::vector<Vec2f> uvs_;
  std::vector<Color> colors_;
  bool any_normals_ = false, any_without_normals_ = false, any_uvs_ = false, any_without_uvs_ = false,
       any_colors_ = false, any_without_colors_ = false;
};

}  // namespace

void read_gltf(std::string_view bytes, const std::string& name, bool binary, const ReadOptions& options,
               ReadResult& result) {
  if (bytes.empty()) throw ParseError(name, "the file is empty", std::nullopt, std::nullopt);
  GltfReader(bytes, name, options, result).read(binary);
}

}  // namespace cgview::detail
