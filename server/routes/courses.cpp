// /api/v1/courses...: courses, their members and sign-in links
// (teaching/courses.h).  A course's assignments are in assignments.cpp.
#include "core/errors.h"
#include "io/parse_json.h"
#include "router.h"
#include "routes/routes.h"
#include "teaching/courses.h"

namespace cgview::server {

using nlohmann::json;

namespace {

json object_body(const HttpRequest& req) {
  const json body = req.body.empty() ? json::object() : parse_json_or_discarded(req.body);
  if (!body.is_object()) throw InvalidInput("the body is not a JSON object");
  return body;
}

// A link's lifetime: the body's "link_expires_s" (when it is a JSON object
// with one), else the query's, else three days; throws BadParameter.
std::chrono::seconds link_life(const HttpRequest& req, const json& body) {
  if (body.is_object() && body.contains("link_expires_s")) {
    if (!body["link_expires_s"].is_number_integer())
      throw BadParameter("link_expires_s", "link_expires_s is a number of seconds (60 to a week)");
    return std::chrono::seconds(body["link_expires_s"].get<long long>());
  }
  return std::chrono::seconds(
      int_param(split_target(req.target).second, "link_expires_s", int(Courses::kDefaultLinkLife.count())));
}

// A roster is CSV unless it begins as JSON does.
bool is_csv(const std::string& body) {
  const auto first = body.find_first_not_of(" \t\r\n");
  return first == std::string::npos || (body[first] != '[' && body[first] != '{');
}

}  // namespace

void add_course_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back({"GET",
                    "/api/v1/courses",
                    "The courses you are in, with your role in each (teacher, assistant or student)",
                    {},
                    [&ctx](const Params&, const HttpRequest&, const Caller& caller) {
                      return json_response(200, ctx.courses().list(caller));
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/courses",
                    "Create a course (a teacher): {\"title\"}; you are its teacher",
                    {},
                    [&ctx](const Params&, const HttpRequest& req, const Caller& caller) {
                      const json c = ctx.courses().create(object_body(req), caller);
                      HttpResponse r = json_response(201, c);
                      r.headers.push_back({"Location", "/api/v1/courses/" + c["id"].get<std::string>()});
                      return r;
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/courses/{id}",
                    "One course: its title and your role; its staff also see the members, a teacher the join code",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(200, ctx.courses().get(p.at("id"), caller));
                    },
                    false});
  routes.push_back(
      {"POST",
       "/api/v1/courses/{id}/members",
       "Enrol a roster (a teacher): a JSON list of {\"login\", \"name\", \"role\"} (role student, assistant or "
       "teacher) or CSV lines login,name[,role]; missing accounts are made, and each gets a one-time sign-in link "
       "(\"links\": [{\"user\", \"ticket\"}], redeemed at /api/v1/tickets/redeem)",
       {{"link_expires_s", "how long the sign-in links live, 60 s to a week (default three days)"}},
       [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
         const bool csv = is_csv(req.body);
         const json body = csv ? json() : parse_json_or_discarded(req.body);
         return json_response(200, ctx.courses().add_members(p.at("id"), req.body, csv, link_life(req, body), caller));
       }});
  routes.push_back({"DELETE",
                    "/api/v1/courses/{id}/members/{user}",
                    "Remove a member (a teacher): what is shared with the course is theirs to read no more",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      ctx.courses().remove_member(p.at("id"), p.at("user"), caller);
                      HttpResponse r;
                      r.status = 204;
                      return r;
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/courses/{id}/members/{user}/link",
                    "A new one-time sign-in link for a member (a teacher): body {\"link_expires_s\"}",
                    {},
                    [&ctx](const Params& p, const HttpRequest& req, const Caller& caller) {
                      return json_response(200, ctx.courses().new_link(p.at("id"), p.at("user"),
                                                                       link_life(req, object_body(req)), caller));
                    },
                    false});
  routes.push_back({"POST",
                    "/api/v1/courses/join",
                    "Join a course as a student with its join code: {\"code\"}",
                    {},
                    [&ctx](const Params&, const HttpRequest& req, const Caller& caller) {
                      const json body = object_body(req);
                      if (!body.value("code", json()).is_string())
                        throw InvalidInput("the body is {\"code\": \"the course's join code\"}");
                      const auto joined = ctx.courses().join(body["code"], caller);
                      if (!joined) return error_response(404, "not_found", "no course has that join code");
                      return json_response(200, *joined);
                    },
                    false});
}

}  // namespace cgview::server
