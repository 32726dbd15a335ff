// /api/v1/courses/{id}/assignments, /api/v1/assignments/... and
// /api/v1/submissions/...: exercises graded on hidden meshes
// (teaching/grading.h).
#include "core/errors.h"
#include "io/parse_json.h"
#include "render/renderer_pool.h"
#include "render_service.h"
#include "router.h"
#include "routes/routes.h"
#include "teaching/grading.h"

namespace cgview::server {

using nlohmann::json;

namespace {

json body_json(const HttpRequest& req) {
  const json body = parse_json_or_discarded(req.body);
  if (body.is_discarded()) throw InvalidInput("the body is not JSON");
  return body;
}

bool late_counts(const HttpRequest& req) {
  const std::string v = text_param(split_target(req.target).second, "late", "exclude");
  if (v != "include" && v != "exclude") throw BadParameter("late", "parameter 'late': include or exclude");
  return v == "include";
}

}  // namespace

void add_assignment_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back(
      {"POST",
       "/api/v1/courses/{id}/assignments",
       "Post an assignment (a teacher): {\"title\", \"statement\" (Markdown), \"starter\" (C++), \"public_meshes\", "
       "\"hidden_meshes\", \"reference_plugin\", \"algorithm\", \"output\", \"params\", \"compare\": {\"method\", "
       "\"tolerance\", \"keys\"}, \"points_per_mesh\", \"deadline\", \"show_pictures\", \"time_limit_s\"}; the "
       "reference runs on every hidden mesh",
       {},
       [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
         const json a = ctx.grading().create(p.at("id"), body_json(req), caller);
         HttpResponse r = json_response(201, a);
         r.headers.push_back({"Location", "/api/v1/assignments/" + a["id"].get<std::string>()});
         return r;
       }});
  routes.push_back({"GET",
                    "/api/v1/courses/{id}/assignments",
                    "A course's assignments, as its members see them",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(200, ctx.grading().list(p.at("id"), caller));
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/assignments/{id}",
                    "One assignment: its statement, starter, public meshes, deadline and points (its staff: also the "
                    "hidden meshes and the reference's runs)",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(200, ctx.grading().get(p.at("id"), caller));
                    },
                    false});
  routes.push_back(
      {"POST",
       "/api/v1/assignments/{id}/submissions",
       "Submit a solution: {\"source\": C++ TEXT} or {\"plugin\": your plugin's id}; it is built, run on every hidden "
       "mesh and scored (GET the submission for its state and scores)",
       {},
       [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
         const json s = ctx.grading().submit(p.at("id"), body_json(req), caller);
         HttpResponse r = json_response(202, s);
         r.headers.push_back({"Location", "/api/v1/submissions/" + s["id"].get<std::string>()});
         return r;
       }});
  routes.push_back({"GET",
                    "/api/v1/assignments/{id}/submissions",
                    "An assignment's submissions: your own; its staff: everyone's",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(200, ctx.grading().submissions(p.at("id"), caller));
                    },
                    false});
  routes.push_back(
      {"GET",
       "/api/v1/assignments/{id}/grades",
       "The grades (its staff): a row per student, as JSON or as CSV for Moodle's and Canvas's gradebook imports",
       {{"format", "json (default) or csv"},
        {"late", "exclude (default: the latest submission before the deadline counts) or include (the latest)"}},
       [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
         const std::string format = text_param(split_target(req.target).second, "format", "json");
         const bool late = late_counts(req);
         if (format == "json") return json_response(200, ctx.grading().grades(p.at("id"), late, caller));
         if (format != "csv") throw BadParameter("format", "parameter 'format': json or csv");
         HttpResponse r;
         r.body = ctx.grading().grades_csv(p.at("id"), late, caller);
         r.content_type = "text/csv; charset=utf-8";
         r.headers.push_back({"Content-Disposition", "attachment; filename=\"grades-" + p.at("id") + ".csv\""});
         return r;
       },
       false});
  routes.push_back({"POST",
                    "/api/v1/assignments/{id}/regrade",
                    "Grade every submission again (its staff); an unchanged one gets the same scores",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(202, ctx.grading().regrade(p.at("id"), caller));
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/submissions/{id}",
                    "One submission: its state, build, score and a result per hidden mesh with its reason",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(200, ctx.grading().submission(p.at("id"), caller));
                    },
                    false});
  routes.push_back(
      {"GET",
       "/api/v1/submissions/{id}/pictures/{n}/{which}",
       "A picture of a submission's result on hidden mesh n (which: result.png, reference.png or, for a field, "
       "difference.png); students see them where the assignment shows pictures",
       {{"width", "pixels, 1..2048 (default 480)"}, {"height", "pixels, 1..2048 (default 360)"}},
       [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
         std::string which = p.at("which");
         if (!which.ends_with(".png")) throw std::out_of_range("no picture '" + which + "'");
         which.resize(which.size() - 4);
         std::size_t n = 0;
         try {
           n = std::stoul(p.at("n"));
         } catch (const std::exception&) {
           throw std::out_of_range("no result '" + p.at("n") + "'");
         }
         const Grading::Picture pic = ctx.grading().picture(p.at("id"), n, which, caller);
         render::RenderParams params;
         const Query q = split_target(req.target).second;
         auto size = [&](const char* name, int otherwise) {
           const int v = int_param(q, name, otherwise);
           if (v < 1 || v > 2048) throw BadParameter(name, std::string("parameter '") + name + "': 1..2048");
           return v;
         };
         params.width = size("width", 480);
         params.height = size("height", 360);
         return png_response(ctx, *pic.mesh, pic.field ? &*pic.field : nullptr, params);
       }});
}

}  // namespace cgview::server
