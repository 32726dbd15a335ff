// The HTTP router: a request in, a response out, no sockets (Beast's
// advanced_server handle_request).  Tests call it directly; the HTTP session
// calls it on a worker thread.  Every route is declared once in a table
// (routes/: one file a resource), from which the OpenAPI document is made.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "auth.h"
#include "mesh_service.h"
#include "render/egl_context.h"
#include "routes/http.h"
#include "routes/routes.h"

namespace cgview::server {

class Courses;
class Grading;
class Rooms;
class PluginService;

class JobScheduler;
class Metrics;
class RenderService;

struct RouterConfig {
  std::filesystem::path static_dir;  // the built web client; empty: none
  std::string version = "0.1.0";
  JobScheduler* jobs = nullptr;  // the algorithm and job routes answer 503 without one
  render::GlPlatform gl_platform = render::GlPlatform::automatic;  // for render.png
  int renderers = 2;                                               // EGL contexts rendering at once (render.png)
  bool auth_required = false;        // every /api/ request needs a bearer token (else: Caller::local() without one)
  Metrics* metrics = nullptr;        // counts every request; GET /metrics serves it (404 without one)
  PluginService* plugins = nullptr;  // users' plugins; the plugin routes answer 500 without one
  Courses* courses = nullptr;        // courses and members (teaching/courses.h); none: no groups, 500
  Grading* grading = nullptr;        // assignments and submissions (teaching/grading.h)
  Rooms* rooms = nullptr;            // live lectures and their recordings (teaching/rooms.h)
};

class Router {
 public:
  using Route = server::Route;

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
  MeshService& meshes_;
  RouterConfig config_;
  Auth auth_;
  RouteContext context_;  // what the route groups' handlers reach
  Routes routes_;
};

}  // namespace cgview::server
