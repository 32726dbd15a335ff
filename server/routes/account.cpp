#include "routes/routes.h"

#include "jobs/scheduler.h"
#include "metrics.h"
#include "router.h"
#include "store.h"

namespace cgview::server {

using nlohmann::json;

void add_account_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back({"GET",
                    "/metrics",
                    "Prometheus metrics (text format): requests, latencies, WebSockets, jobs, queue, store",
                    {},
                    [&ctx](const Params&, const HttpRequest&, const Caller&) {
                      if (!ctx.config.metrics) return error_response(404, "not_found", "this server keeps no metrics");
                      MetricsSnapshot now;
                      now.meshes = ctx.meshes.store().count();
                      now.store_bytes = ctx.meshes.store().total_bytes();
                      if (ctx.config.jobs) {
                        const JobCounts c = ctx.config.jobs->counts();
                        now.jobs = c.by_state_algorithm;
                        now.queued = c.queued;
                        now.running = c.running;
                        now.store_bytes += c.artifact_bytes;
                      }
                      HttpResponse r;
                      r.content_type = Metrics::kContentType;
                      r.body = ctx.config.metrics->text(now);
                      return r;
                    }});
  routes.push_back({"GET",
                    "/api/v1/health",
                    "Server health: status, version, mesh count, uptime",
                    {},
                    [&ctx](const Params&, const HttpRequest&, const Caller& caller) {
                      const double up =
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - ctx.started).count();
                      return json_response(200, {{"status", "ok"},
                                                 {"version", ctx.config.version},
                                                 {"meshes", ctx.meshes.store().count(caller)},
                                                 {"uptime_s", up}});
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/me",
                    "The caller: user name, admin, storage and jobs used and their limits (null: none)",
                    {},
                    [&ctx](const Params&, const HttpRequest&, const Caller& caller) {
                      // Without a job scheduler (tests of the router alone) only meshes count, unlimited.
                      const Usage use = ctx.config.jobs ? ctx.config.jobs->usage(caller.user)
                                                        : Usage{ctx.meshes.store().mesh_bytes(caller.user), 0};
                      const UserLimits lim = ctx.config.jobs ? ctx.config.jobs->limits(caller) : UserLimits{};
                      auto or_null = [](const auto& v) { return v ? json(*v) : json(nullptr); };
                      return json_response(200, {{"user", caller.user},
                                                 {"admin", caller.admin},
                                                 {"teacher", caller.teacher || caller.admin},
                                                 {"storage_bytes_used", use.storage_bytes},
                                                 {"storage_bytes_limit", or_null(lim.storage_bytes)},
                                                 {"jobs_active", use.jobs_active},
                                                 {"jobs_limit", or_null(lim.concurrent_jobs)}});
                    },
                    false});
}

}  // namespace cgview::server
