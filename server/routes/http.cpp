#include "routes/http.h"

#include <cmath>

#include "io/mesh_formats.h"

namespace cgview::server {

using nlohmann::json;

namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string percent_decode(std::string_view s, bool plus_is_space) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && hex_value(s[i + 1]) >= 0 && hex_value(s[i + 2]) >= 0) {
      out.push_back(char(hex_value(s[i + 1]) * 16 + hex_value(s[i + 2])));
      i += 2;
    } else if (s[i] == '+' && plus_is_space) {
      out.push_back(' ');
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

}  // namespace

HttpResponse json_response(int status, const json& body) {
  HttpResponse r;
  r.status = status;
  // A detail may quote a file's bytes (a parser's message): invalid UTF-8
  // there is replaced, not a reason to fail the answer.
  r.body = body.dump(-1, ' ', false, json::error_handler_t::replace);
  return r;
}

HttpResponse error_response(int status, const std::string& code, const std::string& detail) {
  return json_response(status, json{{"error", code}, {"detail", detail}});
}

HttpResponse bad_parameter(const BadParameter& e) {
  return json_response(400, json{{"error", "bad_request"}, {"detail", e.what()}, {"parameter", e.parameter}});
}

std::pair<std::string, std::map<std::string, std::string>> split_target(const std::string& target) {
  const std::size_t qm = target.find('?');
  std::string path = percent_decode(target.substr(0, qm), false);
  std::map<std::string, std::string> query;
  if (qm != std::string::npos) {
    std::string_view rest(target);
    rest.remove_prefix(qm + 1);
    while (!rest.empty()) {
      const std::size_t amp = rest.find('&');
      const std::string_view pair = rest.substr(0, amp);
      const std::size_t eq = pair.find('=');
      if (!pair.empty())
        query[percent_decode(pair.substr(0, eq), true)] =
            eq == std::string_view::npos ? "" : percent_decode(pair.substr(eq + 1), true);
      if (amp == std::string_view::npos) break;
      rest.remove_prefix(amp + 1);
    }
  }
  return {path, query};
}

const char* content_type_of(const std::string& extension) {
  static const std::map<std::string, const char*> types = {{".html", "text/html; charset=utf-8"},
                                                           {".js", "text/javascript"},
                                                           {".mjs", "text/javascript"},
                                                           {".css", "text/css"},
                                                           {".json", "application/json"},
                                                           {".wasm", "application/wasm"},
                                                           {".svg", "image/svg+xml"},
                                                           {".png", "image/png"},
                                                           {".ico", "image/x-icon"},
                                                           {".txt", "text/plain; charset=utf-8"},
                                                           {".map", "application/json"}};
  const auto it = types.find(extension);
  if (it != types.end()) return it->second;
  if (const MeshFormatInfo* mesh = mesh_format_of_extension(extension)) return mesh->mime;
  return "application/octet-stream";
}

double number_param(const Query& q, const std::string& name, double fallback) {
  const auto it = q.find(name);
  if (it == q.end()) return fallback;
  try {
    std::size_t used = 0;
    const double v = std::stod(it->second, &used);
    if (used == it->second.size() && std::isfinite(v)) return v;
  } catch (const std::logic_error&) {
  }
  throw BadParameter(name, "parameter '" + name + "': '" + it->second + "' is not a number");
}

int int_param(const Query& q, const std::string& name, int fallback) {
  const double v = number_param(q, name, fallback);
  if (v != std::floor(v) || std::abs(v) > 1e9)
    throw BadParameter(name, "parameter '" + name + "': '" + q.at(name) + "' is not an integer");
  return int(v);
}

std::string text_param(const Query& q, const std::string& name, const std::string& fallback) {
  const auto it = q.find(name);
  return it == q.end() ? fallback : it->second;
}

}  // namespace cgview::server
