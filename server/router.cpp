#include "router.h"

#include <chrono>
#include <cmath>
#include <cctype>
#include <fstream>

#include "core/ascii.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "jobs/scheduler.h"
#include "metrics.h"
#include "render_service.h"
#include "teaching/courses.h"
#include "teaching/rooms.h"
#include "io/zip_bundle.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Matches "/api/v1/meshes/{id}" against a path, filling the named parts.
bool match(const std::string& pattern, const std::string& path, std::map<std::string, std::string>& params) {
  std::size_t p = 0, q = 0;
  while (p < pattern.size() && q <= path.size()) {
    if (pattern[p] == '{') {
      const std::size_t close = pattern.find('}', p);
      const std::string name = pattern.substr(p + 1, close - p - 1);
      const std::size_t end = path.find('/', q);
      const std::string value = path.substr(q, end == std::string::npos ? std::string::npos : end - q);
      if (value.empty()) return false;
      params[name] = value;
      p = close + 1;
      q = end == std::string::npos ? path.size() : end;
    } else {
      if (q >= path.size() || pattern[p] != path[q]) return false;
      ++p;
      ++q;
    }
  }
  return p == pattern.size() && q == path.size();
}

// Ids and names in a route's path are never paths: only what an id or an
// artifact name can be ([A-Za-z0-9_.-], not "." or ".."), so that "..",
// a decoded "%2F" or a NUL is refused before any handler (or file) sees it.
bool valid_path_param(const std::string& v) {
  if (v.empty() || v.size() > 128 || v == "." || v == "..") return false;
  for (unsigned char c : v)
    if (!std::isalnum(c) && c != '_' && c != '.' && c != '-') return false;
  return true;
}

}  // namespace

Router::Router(MeshService& meshes, RouterConfig config)
    : meshes_(meshes),
      config_(std::move(config)),
      auth_(meshes_.store(), config_.auth_required),
      context_{meshes_, config_, std::make_shared<RenderService>(config_.gl_platform, config_.renderers),
               [this](const json& event, const Access& readers) {
                 if (on_event) on_event(event, readers);
               }} {
  context_.auth = &auth_;
  // A caller's groups: their courses' and the live rooms they present or follow.
  if (config_.courses)
    auth_.set_groups([c = config_.courses, r = config_.rooms](const std::string& user) {
      auto groups = c->groups_of(user);
      if (r)
        for (auto& g : r->groups_of(user)) groups.push_back(std::move(g));
      return groups;
    });
  add_account_routes(routes_, context_);
  add_ticket_routes(routes_, context_);
  add_mesh_routes(routes_, context_);
  add_render_route(routes_, context_);
  add_job_routes(routes_, context_);
  add_data_routes(routes_, context_);
  add_worker_routes(routes_, context_);
  add_plugin_routes(routes_, context_);
  add_course_routes(routes_, context_);
  add_assignment_routes(routes_, context_);
  add_room_routes(routes_, context_);
  routes_.push_back({"GET",
                     "/api/v1/openapi.json",
                     "This API's OpenAPI 3 document",
                     {},
                     [this](const Params&, const HttpRequest&, const Caller&) { return json_response(200, openapi()); },
                     false});
}

bool Router::is_heavy(const HttpRequest& req) const {
  const std::string path = split_target(req.target).first;
  std::map<std::string, std::string> params;
  for (const Route& r : routes_)
    if (r.method == req.method && match(r.pattern, path, params)) return r.heavy;
  return true;
}

HttpResponse Router::handle(const HttpRequest& req) const {
  const auto t0 = std::chrono::steady_clock::now();
  std::string route = "unmatched";
  HttpResponse r = dispatch(req, route);
  if (config_.metrics)
    config_.metrics->request(route, req.method, r.status,
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return r;
}

HttpResponse Router::dispatch(const HttpRequest& req, std::string& route) const {
  const auto [path, query] = split_target(req.target);
  // The web client's files are public (it asks for a token); the API and the metrics are not.
  std::optional<Caller> caller;
  // A worker's routes take its job's token instead (JobScheduler::worker_*); a
  // ticket's redemption takes the ticket (routes/tickets.cpp).
  if ((path.starts_with("/api/") || path == "/metrics") && !path.starts_with("/api/v1/worker/") &&
      path != "/api/v1/tickets/redeem") {
    caller = auth_.authenticate(req.authorization);
    if (!caller) {
      HttpResponse r =
          error_response(401, "unauthorized",
                         req.authorization.empty() ? "this server needs a token: Authorization: Bearer TOKEN"
                                                   : "the token is wrong or was revoked");
      r.headers.push_back({"WWW-Authenticate", "Bearer"});
      return r;
    }
  }
  bool path_known = false;
  for (const Route& r : routes_) {
    std::map<std::string, std::string> params;
    if (!match(r.pattern, path, params)) continue;
    path_known = true;
    if (r.method != req.method) continue;
    route = r.pattern;
    for (const auto& [name, value] : params)
      if (!valid_path_param(value))
        return error_response(400, "bad_request",
                              "'" + name + "' is not a valid " + name + ": letters, digits, '_', '.' or '-'");
    try {
      return r.handler(params, req, caller.value_or(Caller::local()));
    } catch (const WorkerTokenRefused& e) {
      HttpResponse res = error_response(401, "unauthorized", e.what());
      res.headers.push_back({"WWW-Authenticate", "Bearer"});
      return res;
    } catch (const QuotaExceeded& e) {
      HttpResponse res =
          json_response(e.status, json{{"error", e.code}, {"detail", e.what()}, {"limit", e.limit}, {"used", e.used}});
      if (e.status == 429) res.headers.push_back({"Retry-After", std::to_string(e.retry_after_s)});
      return res;
    } catch (const Forbidden& e) {
      return error_response(403, "forbidden", e.what());
    } catch (const BadParameter& e) {
      return bad_parameter(e);
    } catch (const UnsupportedFormat& e) {
      return error_response(400, "unsupported_format", e.what());
    } catch (const TooLarge& e) {
      return error_response(413, "payload_too_large", e.what());
    } catch (const InvalidInput& e) {
      return error_response(400, "invalid_mesh", e.what());
    } catch (const std::out_of_range& e) {
      return error_response(404, "not_found", e.what());
    } catch (const DiskFull&) {
      return error_response(507, "insufficient_storage",
                            "the server's storage is full: nothing was stored; retry once space is freed");
    } catch (const std::exception& e) {
      return error_response(500, "internal", e.what());
    }
  }
  if (path_known) return error_response(405, "method_not_allowed", req.method + " is not allowed on " + path);
  if (path.starts_with("/api/")) return error_response(404, "not_found", "no route " + req.method + " " + path);
  if (req.method != "GET" && req.method != "HEAD")
    return error_response(405, "method_not_allowed", "only GET serves files");
  route = "static";
  return serve_static(config_.static_dir, path);
}

json Router::openapi() const {
  json paths = json::object();
  for (const Route& r : routes_) {
    json op{{"summary", r.summary}, {"responses", json::object()}};
    json params = json::array();
    for (std::size_t p = r.pattern.find('{'); p != std::string::npos; p = r.pattern.find('{', p + 1)) {
      const std::string name = r.pattern.substr(p + 1, r.pattern.find('}', p) - p - 1);
      params.push_back({{"name", name}, {"in", "path"}, {"required", true}, {"schema", {{"type", "string"}}}});
    }
    for (const auto& [name, help] : r.query)
      params.push_back({{"name", name}, {"in", "query"}, {"description", help}, {"schema", {{"type", "string"}}}});
    if (!params.empty()) op["parameters"] = params;
    const json error_ref = {
        {"description", "error"},
        {"content", {{"application/json", {{"schema", {{"$ref", "#/components/schemas/Error"}}}}}}}};
    op["responses"]["200"] = {{"description", "success"}};
    const bool is_job = r.pattern.starts_with("/api/v1/jobs");
    const bool json_body = r.pattern != "/api/v1/meshes";  // every POST but the upload takes JSON
    if (r.method == "POST" && json_body) {
      op["requestBody"] = {{"content", {{"application/json", {{"schema", {{"type", "object"}}}}}}}};
      if (r.pattern == "/api/v1/jobs") {
        op["responses"].erase("200");
        op["responses"]["201"] = {{"description", "created"}};
        op["responses"]["413"] = error_ref;  // no room left under the storage quota
        op["responses"]["429"] = error_ref;  // the concurrent job limit
      } else {
        op["responses"]["403"] = error_ref;  // share, unshare: only the owner
      }
    } else if (r.method == "POST") {
      // The mesh file, or a zip of it with its MTL and images (README "Textured meshes").
      const json binary = {{"schema", {{"type", "string"}, {"format", "binary"}}}};
      op["requestBody"] = {{"content", {{"application/octet-stream", binary}, {"application/zip", binary}}}};
      op["responses"].erase("200");
      op["responses"]["201"] = {{"description", "created"}};
      op["responses"]["413"] = error_ref;
    }
    if (r.method == "DELETE" && !is_job) {
      op["responses"].erase("200");
      op["responses"]["204"] = {{"description", "deleted"}};
    }
    if (r.method == "DELETE") op["responses"]["403"] = error_ref;  // a shared item: only its owner
    op["responses"]["400"] = error_ref;
    if (r.pattern.find('{') != std::string::npos || (is_job && r.method == "POST")) op["responses"]["404"] = error_ref;
    op["responses"]["401"] = error_ref;
    paths[r.pattern][ascii_lower(r.method)] = op;
  }
  paths["/api/v1/ws"]["get"] = {
      {"summary", "WebSocket: JSON requests and events, binary mesh frames (protocol/API.md)"},
      {"responses", {{"101", {{"description", "switching protocols"}}}}}};
  json error_schema = {{"type", "object"},
                       {"properties", {{"error", {{"type", "string"}}}, {"detail", {{"type", "string"}}}}},
                       {"required", {"error", "detail"}}};
  json doc;
  doc["openapi"] = "3.0.3";
  doc["info"] = {{"title", "CGView API"}, {"version", config_.version}};
  doc["paths"] = paths;
  doc["components"]["schemas"]["Error"] = error_schema;
  // On loopback a server needs no token; elsewhere (or with --auth required) every route does.
  doc["components"]["securitySchemes"]["bearer"] = {{"type", "http"}, {"scheme", "bearer"}};
  doc["security"] = json::array({{{"bearer", json::array()}}, json::object()});
  return doc;
}

}  // namespace cgview::server
