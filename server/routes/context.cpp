// What the route groups share (routes.h): the job scheduler, the mesh a
// caller may read or change, sharing; and the web client's static files.
#include <fstream>

#include "core/errors.h"
#include "io/parse_json.h"
#include "mesh_service.h"
#include "router.h"
#include "routes/routes.h"
#include "store.h"
#include "teaching/courses.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

JobScheduler& RouteContext::jobs() const {
  if (!config.jobs) throw std::runtime_error("this server runs no jobs");
  return *config.jobs;
}

MeshRecord RouteContext::mesh(const std::string& id, const Caller& caller) const {
  auto rec = meshes.store().get_mesh(id, caller);
  if (!rec) throw std::out_of_range("no mesh with id '" + id + "'");
  return *rec;
}

MeshRecord RouteContext::owned_mesh(const std::string& id, const Caller& caller) const {
  MeshRecord rec = mesh(id, caller);
  if (!Access{rec.owner}.owned_by(caller))
    throw Forbidden("mesh " + rec.id + " is " + rec.owner + "'s: only its owner changes it");
  return rec;
}

Courses& RouteContext::courses() const {
  if (!config.courses) throw std::runtime_error("this server has no courses");
  return *config.courses;
}

Grading& RouteContext::grading() const {
  if (!config.grading) throw std::runtime_error("this server grades no assignments (it runs no jobs)");
  return *config.grading;
}

HttpResponse RouteContext::share(const std::string& kind, const std::string& id, const std::string& owner,
                                 const HttpRequest& req, bool add, const Caller& caller) const {
  const json body = parse_json_or_discarded(req.body);
  const char* shape =
      "the body is {\"users\": [NAME, ...]}, {\"courses\": [COURSE_ID, ...]} and/or {\"everyone\": true}";
  if (!body.is_object()) return error_response(400, "bad_request", shape);
  std::vector<std::string> users;
  const json names = body.value("users", json::array());
  if (!names.is_array()) return error_response(400, "bad_request", shape);
  for (const auto& n : names) {
    if (!n.is_string()) return error_response(400, "bad_request", shape);
    if (!meshes.store().get_user(n))
      return error_response(400, "bad_request", "no user '" + n.get<std::string>() + "'");
    users.push_back(n);
  }
  // A course's group: its members read the item (teaching/courses.h); only a member shares with it.
  const json courses = body.value("courses", json::array());
  if (!courses.is_array()) return error_response(400, "bad_request", shape);
  for (const auto& c : courses) {
    if (!c.is_string()) return error_response(400, "bad_request", shape);
    if (!config.courses || !config.courses->role(c, caller))
      return error_response(404, "not_found", "no course with id '" + c.get<std::string>() + "'");
    users.push_back(Courses::group(c));
  }
  const json everyone = body.value("everyone", json(false));
  if (!everyone.is_boolean()) return error_response(400, "bad_request", shape);
  if (everyone.get<bool>()) users.push_back(kEveryone);
  if (users.empty()) return error_response(400, "bad_request", shape);
  meshes.store().set_shared(kind, id, users, add);
  const Access a = meshes.store().access(kind, id, owner);
  return json_response(200, {{"id", id}, {"owner", a.owner}, {"users", a.readers}, {"everyone", a.everyone}});
}

HttpResponse serve_static(const fs::path& static_dir, const std::string& path) {
  if (static_dir.empty()) return error_response(404, "not_found", "no web client is served (--static-dir)");
  if (path.find("..") != std::string::npos || path.find('\0') != std::string::npos || path.empty() || path[0] != '/')
    return error_response(400, "bad_request", "bad path");
  // "//etc/passwd" (or "/%2Fetc...") leaves an absolute path after the first
  // '/', and dir / absolute is the absolute path itself: refuse it.
  const fs::path relative = path.substr(1);
  if (relative.has_root_path()) return error_response(400, "bad_request", "bad path");
  fs::path file = static_dir / relative;
  std::error_code ec;
  if (path == "/" || fs::is_directory(file, ec)) file /= "index.html";
  std::ifstream f(file, std::ios::binary);
  if (!f) return error_response(404, "not_found", "no file " + path);
  HttpResponse r;
  r.body.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  r.content_type = content_type_of(file.extension().string());
  if (path.starts_with("/assets/")) r.headers.push_back({"Cache-Control", "public, max-age=31536000, immutable"});
  return r;
}

}  // namespace cgview::server
