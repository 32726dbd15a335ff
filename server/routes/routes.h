// The REST routes, grouped by resource: each group adds its routes to the
// router's table (router.h), from which requests are matched and the
// OpenAPI document is made.  A new route goes in its resource's file.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "auth.h"
#include "routes/http.h"

namespace cgview {
struct Mesh;
struct ScalarField;
namespace render {
struct RenderParams;
}
}  // namespace cgview

namespace cgview::server {

class Courses;
class Grading;
class JobScheduler;
class MeshService;
class RenderService;
struct MeshRecord;
struct RouterConfig;

struct Route {
  std::string method, pattern;  // "/api/v1/meshes/{id}"
  std::string summary;
  std::vector<std::pair<std::string, std::string>> query;  // name, description
  // Called with the authenticated caller: a route answers only with what
  // the caller may read (another user's id is 404, as an unknown one).
  std::function<HttpResponse(const std::map<std::string, std::string>& params, const HttpRequest&, const Caller&)>
      handler;
  // Heavy routes (parsing, encoding, file I/O) run on a worker; light ones
  // (a lookup, a small JSON) may run on the I/O thread, saving two hops.
  bool heavy = true;
};
using Routes = std::vector<Route>;
using Params = std::map<std::string, std::string>;

// What the route groups reach.
struct RouteContext {
  MeshService& meshes;
  const RouterConfig& config;
  std::shared_ptr<RenderService> renders;
  // Sends an event to the WebSocket clients who may read it.
  std::function<void(const nlohmann::json& event, const Access& readers)> emit;
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  // Users, tokens and sign-in tickets (the router's).
  const Auth* auth = nullptr;

  // The job scheduler; throws where the server runs no jobs (a 500 naming it).
  JobScheduler& jobs() const;
  // Courses and their assignments (server/teaching/); the same where there are none.
  Courses& courses() const;
  Grading& grading() const;
  // The mesh `id` if the caller may read it; another user's answers as an
  // unknown id (std::out_of_range: 404).
  MeshRecord mesh(const std::string& id, const Caller& caller) const;
  // The same for a change (delete, share): the owner's or an admin's (Forbidden: 403).
  MeshRecord owned_mesh(const std::string& id, const Caller& caller) const;
  // POST .../share and .../unshare of a mesh, job or plugin (kind "mesh",
  // "job" or "plugin"), once the caller is known to own it: with users, with
  // everyone, or with courses the caller is in (their members read it).
  HttpResponse share(const std::string& kind, const std::string& id, const std::string& owner, const HttpRequest& req,
                     bool add, const Caller& caller) const;
};

// /api/v1/meshes...: list, upload, one, delete, download, textures, share.
void add_mesh_routes(Routes& routes, const RouteContext& ctx);
// GET /api/v1/meshes/{id}/render.png (the offscreen renderer).
void add_render_route(Routes& routes, const RouteContext& ctx);
// A PNG of the mesh (coloured by the field, if any) from the renderer; 503 where it cannot start.
HttpResponse png_response(const RouteContext& ctx, const Mesh& mesh, const ScalarField* field,
                          const render::RenderParams& params);
// /api/v1/algorithms and /api/v1/jobs...: submit, list, one, cancel, artifacts, share.
void add_job_routes(Routes& routes, const RouteContext& ctx);
// POST /api/v1/data: a voxel grid, skeleton or scalar field another tool made.
void add_data_routes(Routes& routes, const RouteContext& ctx);
// /api/v1/worker/jobs/...: a job's worker on a node without the data directory.
void add_worker_routes(Routes& routes, const RouteContext& ctx);
// /api/v1/plugins...: a user's own algorithms (plugin_service.h).
void add_plugin_routes(Routes& routes, const RouteContext& ctx);
// /api/v1/health, /api/v1/me and /metrics.
void add_account_routes(Routes& routes, const RouteContext& ctx);
// /api/v1/courses...: courses, their members and sign-in links (teaching/courses.h).
void add_course_routes(Routes& routes, const RouteContext& ctx);
// /api/v1/courses/{id}/assignments, /api/v1/assignments..., /api/v1/submissions...: graded exercises
// (teaching/grading.h).
void add_assignment_routes(Routes& routes, const RouteContext& ctx);
// /api/v1/courses/{id}/rooms and /api/v1/rooms/{id}/recording: live lectures and their recordings (teaching/rooms.h).
void add_room_routes(Routes& routes, const RouteContext& ctx);
// /api/v1/tickets: sign-in tickets for a page that must not hold a token in its URL (tickets.h).
void add_ticket_routes(Routes& routes, const RouteContext& ctx);

// The built web client's file at a request path (GET anything not under /api/).
HttpResponse serve_static(const std::filesystem::path& static_dir, const std::string& path);

}  // namespace cgview::server
