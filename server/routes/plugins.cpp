// /api/v1/plugins...: a user's own algorithms, saved, built, shared and run
// (plugin_service.h); a plugin's algorithm runs as POST /api/v1/jobs with
// "plugin": its id.
#include "routes/routes.h"

#include "core/errors.h"
#include "io/parse_json.h"
#include "plugin_service.h"
#include "router.h"

namespace cgview::server {

using nlohmann::json;

namespace {

PluginService& plugins(const RouteContext& ctx) {
  if (!ctx.config.plugins) throw std::runtime_error("this server runs no plugins (it runs no jobs)");
  return *ctx.config.plugins;
}

json body_of(const HttpRequest& req) {
  const json body = parse_json_or_discarded(req.body);
  if (body.is_discarded()) throw InvalidInput("the body is not JSON");
  return body;
}

std::string owner_of(const RouteContext& ctx, const std::string& id, const Caller& caller) {
  const Access a = plugins(ctx).access(id, caller);
  if (!a.owned_by(caller) || (a.everyone && a.owner == "lab"))
    throw Forbidden("plugin " + id + " is " + a.owner + "'s: only its owner shares it");
  return a.owner;
}

}  // namespace

void add_plugin_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back({"GET",
                    "/api/v1/plugins",
                    "The plugins you read: your own, those shared with you, the lab's (without their source)",
                    {},
                    [&ctx](const Params&, const HttpRequest&, const Caller& caller) {
                      return json_response(200, plugins(ctx).list(caller));
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/plugins",
                    "Save a new plugin: {\"name\": NAME, \"source\": the algorithm file's C++ text}",
                    {},
                    [&ctx](const Params&, const HttpRequest& req, const Caller& caller) {
                      const json p = plugins(ctx).create(body_of(req), caller);
                      HttpResponse r = json_response(201, p);
                      r.headers.push_back({"Location", "/api/v1/plugins/" + p["id"].get<std::string>()});
                      return r;
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/plugins/{id}",
                    "One plugin, with its source, its build's state, diagnostics and algorithms",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(200, plugins(ctx).get(p.at("id"), caller));
                    },
                    false});
  routes.push_back({"PUT",
                    "/api/v1/plugins/{id}",
                    "Rename a plugin or save its new source: {\"name\"} and/or {\"source\"}",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      return json_response(200, plugins(ctx).update(p.at("id"), body_of(req), caller));
                    },
                    false});
  routes.push_back({"DELETE",
                    "/api/v1/plugins/{id}",
                    "Delete one of your plugins",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      plugins(ctx).remove(p.at("id"), caller);
                      HttpResponse r;
                      r.status = 204;
                      return r;
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/plugins/{id}/build",
                    "Build a plugin's source: a job (algorithm plugin_build) whose end updates the plugin",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(202, plugins(ctx).build(p.at("id"), caller));
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/plugins/{id}/share",
                    "Share a plugin (its owner): {\"users\": [NAME, ...]} and/or {\"everyone\": true}",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      return ctx.share("plugin", p.at("id"), owner_of(ctx, p.at("id"), caller), req, true, caller);
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/plugins/{id}/unshare",
                    "Stop sharing a plugin: the same body as share",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      return ctx.share("plugin", p.at("id"), owner_of(ctx, p.at("id"), caller), req, false, caller);
                    },
                    false});
}

}  // namespace cgview::server
