#include "routes/routes.h"

#include "io/mesh_formats.h"

#include "jobs/scheduler.h"
#include "router.h"
#include "mesh_service.h"
#include "store.h"

namespace cgview::server {

using nlohmann::json;

void add_mesh_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back({"GET",
                    "/api/v1/meshes",
                    "List the stored meshes with their reports",
                    {},
                    [&ctx](const Params&, const HttpRequest&, const Caller& caller) {
                      json list = json::array();
                      for (const auto& r : ctx.meshes.store().list_meshes(caller)) list.push_back(mesh_json(r));
                      return json_response(200, {{"meshes", list}});
                    }});
  routes.push_back({"POST",
                    "/api/v1/meshes",
                    "Upload a mesh: the file's bytes as the raw body, or a zip of it with its MTL and images",
                    {{"name", "the file name, e.g. bunny.ply or spider.zip (required)"},
                     {"format", readable_formats() + " or zip (default: from the name's extension)"}},
                    [&ctx](const Params&, const HttpRequest& req, const Caller& caller) {
                      const auto [path, q] = split_target(req.target);
                      const auto name = q.find("name");
                      if (name == q.end()) return error_response(400, "bad_request", "the query needs ?name=FILE.EXT");
                      const auto format = q.find("format");
                      if (ctx.config.jobs) ctx.config.jobs->check_storage(caller, req.body.size(), "this upload");
                      const MeshRecord rec = ctx.meshes.upload(name->second, format == q.end() ? "" : format->second,
                                                               req.body, caller.user);
                      json j = mesh_json(rec);
                      ctx.emit({{"type", "mesh_added"}, {"mesh", j}}, {rec.owner});
                      HttpResponse r = json_response(201, j);
                      r.headers.push_back({"Location", "/api/v1/meshes/" + rec.id});
                      return r;
                    }});
  routes.push_back({"GET",
                    "/api/v1/formats",
                    "The mesh file formats the server reads and writes (what an upload may be, and the downloads)",
                    {},
                    [](const Params&, const HttpRequest&, const Caller&) {
                      json list = json::array();
                      for (const MeshFormatInfo& f : mesh_formats())
                        list.push_back({{"name", f.name},
                                        {"extensions", f.extensions},
                                        {"mime", f.mime},
                                        {"can_write", f.write != nullptr},
                                        {"points_only", f.points_only},
                                        {"help", f.help}});
                      return json_response(200, {{"formats", list}});
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/meshes/{id}",
                    "One mesh's metadata and report",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      HttpResponse r;
                      r.body = mesh_json_text(ctx.mesh(p.at("id"), caller));
                      return r;
                    },
                    false});
  routes.push_back({"DELETE",
                    "/api/v1/meshes/{id}",
                    "Delete a mesh",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      const MeshRecord rec = ctx.owned_mesh(p.at("id"), caller);
                      const Access readers = ctx.meshes.store().mesh_access(rec.id).value_or(Access{rec.owner});
                      ctx.meshes.store().remove_mesh(rec.id);
                      ctx.emit({{"type", "mesh_deleted"}, {"mesh_id", rec.id}}, readers);
                      HttpResponse r;
                      r.status = 204;
                      r.content_type.clear();
                      return r;
                    }});
  routes.push_back(
      {"GET",
       "/api/v1/meshes/{id}/download",
       "Download a mesh in a format",
       {{"format", writable_formats() + " (default: the uploaded format)"}},
       [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
         const MeshRecord rec = ctx.mesh(p.at("id"), caller);
         const auto q = split_target(req.target).second;
         const auto f = q.find("format");
         const std::string format = f == q.end() ? rec.format : f->second;
         HttpResponse r;
         r.body = ctx.meshes.download(rec, format);
         r.content_type = content_type_of("." + format);
         std::string stem = rec.name.substr(0, rec.name.find_last_of('.'));
         for (char& c : stem)
           if (c == '"' || c == '\\') c = '_';
         r.headers.push_back({"Content-Disposition", "attachment; filename=\"" + stem + "." + format + "\""});
         return r;
       }});
  routes.push_back({"GET",
                    "/api/v1/meshes/{id}/stored_order",
                    "The stored vertex and face of each point and face of the mesh's Draco stream (zlib)",
                    {{"quantization", "the stream's position bits, 1..30 (default 14)"}},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      const MeshRecord rec = ctx.mesh(p.at("id"), caller);
                      HttpResponse r;
                      r.body =
                          ctx.meshes.stored_order(rec, int_param(split_target(req.target).second, "quantization", 14));
                      r.content_type = "application/octet-stream";
                      return r;
                    }});
  routes.push_back({"GET",
                    "/api/v1/meshes/{id}/textures/{n}",
                    "A texture image of a mesh (n: its index in the mesh's textures)",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      const MeshRecord rec = ctx.mesh(p.at("id"), caller);
                      const json textures = material_of(rec)["textures"];
                      const std::string& n = p.at("n");
                      const bool number =
                          !n.empty() && n.size() <= 3 && n.find_first_not_of("0123456789") == std::string::npos;
                      const std::size_t k = number ? std::stoul(n) : textures.size();
                      if (k >= textures.size())
                        throw std::out_of_range("mesh " + rec.id + " has no texture '" + n + "' (it has " +
                                                std::to_string(textures.size()) + ")");
                      HttpResponse r;
                      r.body = ctx.meshes.store().read_texture(rec, k);
                      r.content_type = textures[k].value("mime", "application/octet-stream");
                      return r;
                    }});
  routes.push_back(
      {"POST",
       "/api/v1/meshes/{id}/share",
       "Share a mesh (its owner or an admin): {\"users\":[NAME,...]} and/or {\"everyone\":true}; answers who reads it",
       {},
       [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
         return ctx.share("mesh", p.at("id"), ctx.owned_mesh(p.at("id"), caller).owner, req, true, caller);
       },
       false});
  routes.push_back({"POST",
                    "/api/v1/meshes/{id}/unshare",
                    "Stop sharing a mesh: the same body as share",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      return ctx.share("mesh", p.at("id"), ctx.owned_mesh(p.at("id"), caller).owner, req, false,
                                       caller);
                    },
                    false});
}

}  // namespace cgview::server
