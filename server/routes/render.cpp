// GET /api/v1/meshes/{id}/render.png: a picture of a stored mesh from the
// EGL offscreen renderer, optionally coloured by a job's scalar field.
#include <cmath>

#include "core/errors.h"
#include "jobs/scheduler.h"
#include "mesh_service.h"
#include "render_service.h"
#include "router.h"
#include "routes/routes.h"
#include "store.h"

namespace cgview::server {

using nlohmann::json;

namespace {

// The scalar field that render.png's `field` names (JOB_ID/NAME or NAME).
ScalarField resolve_field(const RouteContext& ctx, const MeshRecord& rec, const std::string& spec,
                          const Caller& caller) {
  auto bad = [](const std::string& why) { return BadParameter("field", "parameter 'field': " + why); };
  if (!ctx.config.jobs) throw bad("this server runs no jobs, so it has no fields");
  std::string job_id, name;
  if (const std::size_t slash = spec.find('/'); slash != std::string::npos) {
    job_id = spec.substr(0, slash);
    name = spec.substr(slash + 1);
  } else {
    name = spec;
    // The newest done job on this mesh with an artifact of that name.
    const json list = ctx.config.jobs->list(caller);
    const json& jobs = list.is_object() && list.contains("jobs") ? list["jobs"] : list;
    for (auto it = jobs.rbegin(); it != jobs.rend(); ++it) {
      const json& j = *it;
      if (j.value("state", "") != "done") continue;
      const json inputs = j.value("inputs", json::object());
      if (!inputs.contains("mesh") || !inputs["mesh"].is_string() || inputs["mesh"].get<std::string>() != rec.id)
        continue;
      for (const auto& a : j.value("artifacts", json::array()))
        if (a.value("name", "") == name && a.value("kind", "") == "scalar_field") job_id = j.value("id", "");
      if (!job_id.empty()) break;
    }
    if (job_id.empty()) throw bad("no done job on mesh " + rec.id + " has a scalar field '" + name + "'");
  }
  if (job_id.empty() || name.empty()) throw bad("'" + spec + "' is not JOB_ID/NAME or NAME");
  try {
    return std::get<ScalarField>(ctx.config.jobs->artifact_value(job_id, name, OutputKind::scalar_field, caller));
  } catch (const UnsupportedFormat&) {
    throw bad("artifact '" + name + "' of job " + job_id + " is not a scalar field");
  } catch (const std::exception& e) {
    throw bad(e.what());
  }
}

// The PNG; a 400 names a bad parameter ("parameter" in the JSON).
HttpResponse render_png(const RouteContext& ctx, const MeshRecord& rec, const HttpRequest& req, const Caller& caller) {
  const auto q = split_target(req.target).second;
  render::RenderParams params;
  std::optional<ScalarField> field;
  try {
    for (const auto& [name, value] : q)
      if (name != "mode" && name != "width" && name != "height" && name != "azimuth" && name != "elevation" &&
          name != "projection" && name != "field")
        throw BadParameter(name, "unknown parameter '" + name + "'");
    if (q.count("mode")) {
      try {
        params.mode = render::parse_render_mode(q.at("mode"), "parameter 'mode'");
      } catch (const InvalidInput& e) {
        throw BadParameter("mode", e.what());
      }
    }
    params.width = int_param(q, "width", 800);
    params.height = int_param(q, "height", 600);
    for (const auto& [name, v] : {std::pair{"width", params.width}, std::pair{"height", params.height}})
      if (v < 1 || v > render::kMaxImageSize)
        throw BadParameter(name, std::string("parameter '") + name + "': must be in [1, " +
                                     std::to_string(render::kMaxImageSize) + "], got " + std::to_string(v));
    params.camera.azimuth = number_param(q, "azimuth", 30);
    params.camera.elevation = number_param(q, "elevation", 20);
    if (params.camera.elevation < -90 || params.camera.elevation > 90)
      throw BadParameter("elevation", "parameter 'elevation': must be in [-90, 90], got " + q.at("elevation"));
    if (q.count("projection")) {
      const std::string& v = q.at("projection");
      if (v == "orthographic") params.camera.projection = render::Projection::orthographic;
      else if (v != "perspective")
        throw BadParameter("projection", "parameter 'projection': '" + v + "' is not perspective or orthographic");
    }
    if (q.count("field")) field = resolve_field(ctx, rec, q.at("field"), caller);
  } catch (const BadParameter& e) {
    return bad_parameter(e);
  }
  const std::shared_ptr<const Mesh> mesh = ctx.meshes.mesh(rec);
  if (field) {
    try {
      field->check_matches(*mesh);
    } catch (const InvalidInput& e) {
      return bad_parameter(BadParameter("field", std::string("parameter 'field': ") + e.what()));
    }
  }
  return png_response(ctx, *mesh, field ? &*field : nullptr, params);
}

}  // namespace

HttpResponse png_response(const RouteContext& ctx, const Mesh& mesh, const ScalarField* field,
                          const render::RenderParams& params) {
  HttpResponse r;
  try {
    r.body = ctx.renders->png(mesh, field, params);
  } catch (const InvalidInput&) {
    throw;
  } catch (const Error& e) {
    return error_response(503, "render_unavailable", e.what());
  }
  r.content_type = "image/png";
  r.headers.push_back({"Cache-Control", "private, max-age=60"});
  return r;
}

void add_render_route(Routes& routes, const RouteContext& ctx) {
  routes.push_back(
      {"GET",
       "/api/v1/meshes/{id}/render.png",
       "A picture of the mesh from the EGL offscreen renderer",
       {{"mode", "points, wireframe, flat, smooth (default) or toon"},
        {"width", "image width in pixels, 1..8192 (default 800)"},
        {"height", "image height in pixels, 1..8192 (default 600)"},
        {"azimuth", "camera azimuth around +y in degrees (default 30)"},
        {"elevation", "camera elevation in degrees, -90..90 (default 20)"},
        {"projection", "perspective (default) or orthographic"},
        {"field", "a scalar-field artifact to colour by: JOB_ID/NAME, or NAME for the newest done job on this mesh"}},
       [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
         return render_png(ctx, ctx.mesh(p.at("id"), caller), req, caller);
       }});
}

}  // namespace cgview::server
