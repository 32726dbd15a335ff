#include "routes/routes.h"

#include "router.h"
#include "io/mesh_io.h"
#include "jobs/scheduler.h"

namespace cgview::server {

using nlohmann::json;

namespace {

// A job's worker on a node without the data directory authenticates with its
// own job's token (Authorization: Bearer), not a user's.
std::string_view worker_token(const HttpRequest& req) {
  return starts_with_nocase(req.authorization, "Bearer ") ? std::string_view(req.authorization).substr(7)
                                                          : std::string_view();
}

}  // namespace

void add_worker_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back({"GET",
                    "/api/v1/worker/jobs/{id}/spec",
                    "A running job's job.json, for its worker (the job's token)",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller&) {
                      HttpResponse r;
                      r.body = ctx.jobs().worker_spec(p.at("id"), worker_token(req));
                      return r;
                    }});
  routes.push_back({"GET",
                    "/api/v1/worker/jobs/{id}/inputs/{name}",
                    "An input file of a running job, for its worker (the job's token)",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller&) {
                      HttpResponse r;
                      r.body = read_file_bytes(ctx.jobs().worker_input(p.at("id"), worker_token(req), p.at("name")),
                                               std::uint64_t(1) << 40);
                      r.content_type = "application/octet-stream";
                      return r;
                    }});
  routes.push_back({"PUT",
                    "/api/v1/worker/jobs/{id}/files/{name}",
                    "A result file of a running job, from its worker (the job's token)",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller&) {
                      ctx.jobs().worker_put(p.at("id"), worker_token(req), p.at("name"), req.body);
                      return json_response(200, json{{"stored", p.at("name")}, {"bytes", req.body.size()}});
                    }});
  routes.push_back({"POST",
                    "/api/v1/worker/jobs/{id}/progress",
                    "A running job's progress line (\"progress F STAGE\"), from its worker (the job's token)",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller&) {
                      ctx.jobs().worker_progress(p.at("id"), worker_token(req), req.body);
                      return json_response(200, json{{"progress", true}});
                    }});
}

}  // namespace cgview::server
