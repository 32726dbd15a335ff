// The HTTP router: a request in, a response out, no sockets (Beast's
// advanced_server handle_request).  Tests call it directly; the HTTP session
// calls it on a worker thread.  Every route is declared once in a table,
// from which the OpenAPI document is generated.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/scalar_field.h"
#include "auth.h"
#include "mesh_service.h"
#include "render/egl_context.h"

namespace cgview::server {

struct HttpRequest {
  std::string method;  // "GET"
  std::string target;  // "/api/v1/meshes?name=x.off"
  std::string body;
  std::string authorization;  // the Authorization header ("Bearer TOKEN"), or empty
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

// An error response: {"error": code, "detail": detail}.
HttpResponse error_response(int status, const std::string& code, const std::string& detail);

class JobScheduler;
class Metrics;
class RenderService;

struct RouterConfig {
  std::filesystem::path static_dir;  // the built web client; empty: none
  std::string version = "0.1.0";
  JobScheduler* jobs = nullptr;  // the algorithm and job routes answer 503 without one
  render::GlPlatform gl_platform = render::GlPlatform::automatic;  // for render.png
  int renderers = 2;  // EGL contexts rendering at once (render.png)
  bool auth_required = false;  // every /api/ request needs a bearer token (else: Caller::local() without one)
  Metrics* metrics = nullptr;  // counts every request; GET /metrics serves it (404 without one)
};

class Router {
 public:
  struct Route {
    std::string method, pattern;  // "/api/v1/meshes/{id}"
    std::string summary;
    std::vector<std::pair<std::string, std::string>> query;  // name, description
    // Called with the authenticated caller: a route answers only with what
    // the caller may read (another user's id is 404, as an unknown one).
    std::function<HttpResponse(const std::map<std::string, std::string>& params, const HttpRequest&, const Caller&)> handler;
    // Heavy routes (parsing, encoding, file I/O) run on a worker; light ones
    // (a lookup, a small JSON) may run on the I/O thread, saving two hops.
    bool heavy = true;
  };

  Router(MeshService& meshes, RouterConfig config);
  HttpResponse handle(const HttpRequest& request) const;
  // True unless the request matches a light route.
  bool is_heavy(const HttpRequest& request) const;
  const std::vector<Route>& routes() const { return routes_; }
  // The OpenAPI 3 document of every route.
  nlohmann::json openapi() const;
  // Called with each event for WebSocket clients (mesh_added, mesh_deleted)
  // and who may see it.
  std::function<void(const nlohmann::json&, const Access&)> on_event;
  // Users and tokens (the WebSocket sessions authenticate with it too).
  const Auth& auth() const { return auth_; }

 private:
  // handle() without the metrics: `route` gets the matched route's pattern.
  HttpResponse dispatch(const HttpRequest& request, std::string& route) const;
  HttpResponse serve_static(const std::string& path) const;
  // GET /api/v1/meshes/{id}/render.png: 400 naming a bad parameter ("parameter" in the JSON).
  HttpResponse render_png(const MeshRecord& rec, const HttpRequest& req, const Caller& caller) const;
  // The scalar field that render.png's `field` names (JOB_ID/NAME or NAME).
  ScalarField resolve_field(const MeshRecord& rec, const std::string& spec, const Caller& caller) const;
  // POST /api/v1/meshes/{id}/share, /unshare and the same for jobs (kind
  // "mesh" or "job"), once the caller is known to own the item.
  HttpResponse share(const std::string& kind, const std::string& id, const std::string& owner, const HttpRequest& req,
                     bool add) const;
  MeshService& meshes_;
  RouterConfig config_;
  Auth auth_;
  std::shared_ptr<RenderService> renders_;
  std::vector<Route> routes_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

// Splits "/a/b?x=1&y=%20" into its path and decoded query parameters.
std::pair<std::string, std::map<std::string, std::string>> split_target(const std::string& target);

}  // namespace cgview::server
