#include "routes/routes.h"

#include "router.h"
#include "core/errors.h"
#include "io/parse_json.h"
#include "jobs/scheduler.h"
#include "mesh_service.h"
#include "plugin_service.h"
#include "store.h"

namespace cgview::server {

using nlohmann::json;

namespace {

// A job shared is its state and artifacts, read-only: only its owner (or an admin) changes who reads it.
std::string job_owner(const RouteContext& ctx, const std::string& id, const Caller& caller) {
  const Access a = ctx.jobs().access(id, caller);
  if (!a.owned_by(caller)) throw Forbidden("job " + id + " is " + a.owner + "'s: only its owner changes it");
  return a.owner;
}

}  // namespace

void add_job_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back({"GET",
                    "/api/v1/algorithms",
                    "The algorithms a job may run, with a JSON Schema of their parameters",
                    {},
                    [&ctx](const Params&, const HttpRequest&, const Caller& caller) {
                      json list = ctx.jobs().algorithms_json();
                      // The caller's plugins' algorithms too, each with "plugin": its id.
                      if (ctx.config.plugins)
                        for (const auto& a : ctx.config.plugins->algorithms_json(caller))
                          list["algorithms"].push_back(a);
                      return json_response(200, list);
                    },
                    false});
  routes.push_back(
      {"POST",
       "/api/v1/jobs",
       "Submit a job: {\"algorithm\",\"inputs\":{\"mesh\":id or {\"job\":id,\"artifact\":name},...},\"params\":{...}}",
       {},
       [&ctx](const Params&, const HttpRequest& req, const Caller& caller) {
         const json body = parse_json_or_discarded(req.body);
         if (body.is_discarded()) return error_response(400, "bad_request", "the body is not JSON");
         json job;
         std::vector<std::string> new_meshes;
         try {
           job = ctx.jobs().submit(body, caller, &new_meshes);
         } catch (const InvalidInput& e) {
           return error_response(400, "bad_request", e.what());
         }
         // A chained job's input mesh is stored: the mesh lists show it.
         for (const auto& id : new_meshes)
           if (const auto rec = ctx.meshes.store().get_mesh(id); rec)
             ctx.emit({{"type", "mesh_added"}, {"mesh", mesh_json(*rec)}}, {rec->owner});
         HttpResponse r = json_response(201, job);
         r.headers.push_back({"Location", "/api/v1/jobs/" + job["id"].get<std::string>()});
         return r;
       },
       false});
  routes.push_back({"GET",
                    "/api/v1/jobs",
                    "List the jobs, oldest first",
                    {},
                    [&ctx](const Params&, const HttpRequest&, const Caller& caller) {
                      return json_response(200, ctx.jobs().list(caller));
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/jobs/{id}",
                    "One job: state, progress, artifacts",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      const auto job = ctx.jobs().get(p.at("id"), caller);
                      if (!job) return error_response(404, "not_found", "no job with id '" + p.at("id") + "'");
                      return json_response(200, *job);
                    },
                    false});
  routes.push_back({"DELETE",
                    "/api/v1/jobs/{id}",
                    "Cancel a queued or running job (answers the job); an ended one is deleted with its results "
                    "(204)",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      const auto removal = ctx.jobs().remove(p.at("id"), caller);
                      if (!removal.found)
                        return error_response(404, "not_found", "no job with id '" + p.at("id") + "'");
                      if (removal.cancelled) return json_response(200, *removal.cancelled);
                      HttpResponse r;
                      r.status = 204;
                      r.content_type.clear();
                      return r;
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/jobs/{id}/cancel",
                    "Cancel a queued or running job (an ended one is left as it is); answers the job",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      const auto job = ctx.jobs().cancel(p.at("id"), caller);
                      if (!job) return error_response(404, "not_found", "no job with id '" + p.at("id") + "'");
                      return json_response(200, *job);
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/jobs/{id}/artifacts/{name}",
                    "An artifact of a done job in a format",
                    {{"format",
                      "scalar field: json (default), f32, txt, csv, ply; mesh: ply (default) or any writable mesh "
                      "format; metrics: json; text: txt; animation: frames"}},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      const auto q = split_target(req.target).second;
                      const auto f = q.find("format");
                      ExportedArtifact a;
                      try {
                        a = ctx.jobs().artifact(p.at("id"), p.at("name"), f == q.end() ? "" : f->second, caller);
                      } catch (const InvalidInput& e) {
                        return error_response(400, "bad_request", e.what());
                      }
                      HttpResponse r;
                      r.body = std::move(a.bytes);
                      r.content_type = a.content_type;
                      r.headers.push_back({"Content-Disposition", "attachment; filename=\"" + a.file_name + "\""});
                      return r;
                    }});
  routes.push_back({"POST",
                    "/api/v1/jobs/{id}/share",
                    "Share a job and its artifacts (its owner or an admin): the same body as a mesh's share",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      return ctx.share("job", p.at("id"), job_owner(ctx, p.at("id"), caller), req, true, caller);
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/jobs/{id}/unshare",
                    "Stop sharing a job",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      return ctx.share("job", p.at("id"), job_owner(ctx, p.at("id"), caller), req, false, caller);
                    },
                    false});
}

}  // namespace cgview::server
