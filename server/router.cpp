#include "router.h"

#include <chrono>
#include <cmath>
#include <cctype>
#include <fstream>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "jobs/scheduler.h"
#include "metrics.h"
#include "render_service.h"
#include "zip_bundle.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string percent_decode(std::string_view s, bool plus_is_space) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && hex_value(s[i + 1]) >= 0 && hex_value(s[i + 2]) >= 0) {
      out.push_back(char(hex_value(s[i + 1]) * 16 + hex_value(s[i + 2])));
      i += 2;
    } else if (s[i] == '+' && plus_is_space) {
      out.push_back(' ');
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

// Matches "/api/v1/meshes/{id}" against a path, filling the named parts.
bool match(const std::string& pattern, const std::string& path, std::map<std::string, std::string>& params) {
  std::size_t p = 0, q = 0;
  while (p < pattern.size() && q <= path.size()) {
    if (pattern[p] == '{') {
      const std::size_t close = pattern.find('}', p);
      const std::string name = pattern.substr(p + 1, close - p - 1);
      const std::size_t end = path.find('/', q);
      const std::string value = path.substr(q, end == std::string::npos ? std::string::npos : end - q);
      if (value.empty()) return false;
      params[name] = value;
      p = close + 1;
      q = end == std::string::npos ? path.size() : end;
    } else {
      if (q >= path.size() || pattern[p] != path[q]) return false;
      ++p;
      ++q;
    }
  }
  return p == pattern.size() && q == path.size();
}

// Ids and names in a route's path are never paths: only what an id or an
// artifact name can be ([A-Za-z0-9_.-], not "." or ".."), so that "..",
// a decoded "%2F" or a NUL is refused before any handler (or file) sees it.
bool valid_path_param(const std::string& v) {
  if (v.empty() || v.size() > 128 || v == "." || v == "..") return false;
  for (unsigned char c : v)
    if (!std::isalnum(c) && c != '_' && c != '.' && c != '-') return false;
  return true;
}

HttpResponse json_response(int status, const json& body) {
  HttpResponse r;
  r.status = status;
  // A detail may quote a file's bytes (a parser's message): invalid UTF-8
  // there is replaced, not a reason to fail the answer.
  r.body = body.dump(-1, ' ', false, json::error_handler_t::replace);
  return r;
}

const char* content_type_of(const std::string& ext) {
  static const std::map<std::string, const char*> types = {
      {".html", "text/html; charset=utf-8"}, {".js", "text/javascript"},      {".mjs", "text/javascript"},
      {".css", "text/css"},                  {".json", "application/json"},   {".wasm", "application/wasm"},
      {".svg", "image/svg+xml"},             {".png", "image/png"},           {".ico", "image/x-icon"},
      {".txt", "text/plain; charset=utf-8"}, {".map", "application/json"},
      {".obj", "model/obj"},                 {".stl", "model/stl"},           {".glb", "model/gltf-binary"}};
  const auto it = types.find(ext);
  return it == types.end() ? "application/octet-stream" : it->second;
}

// A 400 naming the query parameter at fault.
struct BadParameter : std::runtime_error {
  BadParameter(std::string name, const std::string& detail) : std::runtime_error(detail), parameter(std::move(name)) {}
  std::string parameter;
};

double number_param(const std::map<std::string, std::string>& q, const std::string& name, double fallback) {
  const auto it = q.find(name);
  if (it == q.end()) return fallback;
  try {
    std::size_t used = 0;
    const double v = std::stod(it->second, &used);
    if (used == it->second.size() && std::isfinite(v)) return v;
  } catch (const std::logic_error&) {
  }
  throw BadParameter(name, "parameter '" + name + "': '" + it->second + "' is not a number");
}

int int_param(const std::map<std::string, std::string>& q, const std::string& name, int fallback) {
  const double v = number_param(q, name, fallback);
  if (v != std::floor(v) || std::abs(v) > 1e9)
    throw BadParameter(name, "parameter '" + name + "': '" + q.at(name) + "' is not an integer");
  return int(v);
}

}  // namespace

HttpResponse error_response(int status, const std::string& code, const std::string& detail) {
  return json_response(status, json{{"error", code}, {"detail", detail}});
}

std::pair<std::string, std::map<std::string, std::string>> split_target(const std::string& target) {
  const std::size_t qm = target.find('?');
  std::string path = percent_decode(target.substr(0, qm), false);
  std::map<std::string, std::string> query;
  if (qm != std::string::npos) {
    std::string_view rest(target);
    rest.remove_prefix(qm + 1);
    while (!rest.empty()) {
      const std::size_t amp = rest.find('&');
      const std::string_view pair = rest.substr(0, amp);
      const std::size_t eq = pair.find('=');
      if (!pair.empty())
        query[percent_decode(pair.substr(0, eq), true)] =
            eq == std::string_view::npos ? "" : percent_decode(pair.substr(eq + 1), true);
      if (amp == std::string_view::npos) break;
      rest.remove_prefix(amp + 1);
    }
  }
  return {path, query};
}

Router::Router(MeshService& meshes, RouterConfig config)
    : meshes_(meshes),
      config_(std::move(config)),
      auth_(meshes_.store(), config_.auth_required),
      renders_(std::make_shared<RenderService>(config_.gl_platform, config_.renderers)) {
  using Params = std::map<std::string, std::string>;
  // The mesh if the caller may read it; another user's answers as an unknown id.
  auto find = [this](const Params& p, const Caller& caller) {
    auto rec = meshes_.store().get_mesh(p.at("id"), caller);
    if (!rec) throw std::out_of_range("no mesh with id '" + p.at("id") + "'");
    return *rec;
  };
  // The same for a change (delete, share): the owner's or an admin's.
  auto find_owned = [this, find](const Params& p, const Caller& caller) {
    MeshRecord rec = find(p, caller);
    if (!Access{rec.owner}.owned_by(caller)) throw Forbidden("mesh " + rec.id + " is " + rec.owner + "'s: only its owner changes it");
    return rec;
  };
  routes_.push_back({"GET", "/metrics", "Prometheus metrics (text format): requests, latencies, WebSockets, jobs, queue, store", {},
                     [this](const Params&, const HttpRequest&, const Caller&) {
                       if (!config_.metrics) return error_response(404, "not_found", "this server keeps no metrics");
                       MetricsSnapshot now;
                       now.meshes = meshes_.store().count();
                       now.store_bytes = meshes_.store().total_bytes();
                       if (config_.jobs) {
                         const JobCounts c = config_.jobs->counts();
                         now.jobs = c.by_state_algorithm;
                         now.queued = c.queued;
                         now.running = c.running;
                         now.store_bytes += c.artifact_bytes;
                       }
                       HttpResponse r;
                       r.content_type = Metrics::kContentType;
                       r.body = config_.metrics->text(now);
                       return r;
                     }});
  routes_.push_back({"GET", "/api/v1/health", "Server health: status, version, mesh count, uptime", {},
                     [this](const Params&, const HttpRequest&, const Caller& caller) {
                       const double up = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
                       return json_response(200, {{"status", "ok"}, {"version", config_.version},
                                                  {"meshes", meshes_.store().count(caller)}, {"uptime_s", up}});
                     },
                     false});
  routes_.push_back({"GET", "/api/v1/me", "The caller: user name, admin, storage and jobs used and their limits (null: none)", {},
                     [this](const Params&, const HttpRequest&, const Caller& caller) {
                       // Without a job scheduler (tests of the router alone) only meshes count, unlimited.
                       const Usage use = config_.jobs ? config_.jobs->usage(caller.user)
                                                      : Usage{meshes_.store().mesh_bytes(caller.user), 0};
                       const UserLimits lim = config_.jobs ? config_.jobs->limits(caller) : UserLimits{};
                       auto or_null = [](const auto& v) { return v ? json(*v) : json(nullptr); };
                       return json_response(200, {{"user", caller.user}, {"admin", caller.admin},
                                                  {"storage_bytes_used", use.storage_bytes},
                                                  {"storage_bytes_limit", or_null(lim.storage_bytes)},
                                                  {"jobs_active", use.jobs_active},
                                                  {"jobs_limit", or_null(lim.concurrent_jobs)}});
                     },
                     false});
  routes_.push_back({"GET", "/api/v1/meshes", "List the stored meshes with their reports", {},
                     [this](const Params&, const HttpRequest&, const Caller& caller) {
                       json list = json::array();
                       for (const auto& r : meshes_.store().list_meshes(caller)) list.push_back(mesh_json(r));
                       return json_response(200, {{"meshes", list}});
                     }});
  routes_.push_back({"POST", "/api/v1/meshes", "Upload a mesh: the file's bytes as the raw body, or a zip of it with its MTL and images",
                     {{"name", "the file name, e.g. bunny.ply or spider.zip (required)"},
                      {"format", "off, obj, ply, stl, drc, glb, gltf or zip (default: from the name's extension)"}},
                     [this](const Params&, const HttpRequest& req, const Caller& caller) {
                       const auto [path, q] = split_target(req.target);
                       const auto name = q.find("name");
                       if (name == q.end()) return error_response(400, "bad_request", "the query needs ?name=FILE.EXT");
                       const auto format = q.find("format");
                       if (config_.jobs) config_.jobs->check_storage(caller, req.body.size(), "this upload");
                       const MeshRecord rec =
                           meshes_.upload(name->second, format == q.end() ? "" : format->second, req.body, caller.user);
                       json j = mesh_json(rec);
                       if (on_event) on_event({{"type", "mesh_added"}, {"mesh", j}}, {rec.owner});
                       HttpResponse r = json_response(201, j);
                       r.headers.push_back({"Location", "/api/v1/meshes/" + rec.id});
                       return r;
                     }});
  routes_.push_back({"GET", "/api/v1/meshes/{id}", "One mesh's metadata and report", {},
                     [find](const Params& p, const HttpRequest&, const Caller& caller) {
                       HttpResponse r;
                       r.body = mesh_json_text(find(p, caller));
                       return r;
                     },
                     false});
  routes_.push_back({"DELETE", "/api/v1/meshes/{id}", "Delete a mesh", {},
                     [this, find_owned](const Params& p, const HttpRequest&, const Caller& caller) {
                       const MeshRecord rec = find_owned(p, caller);
                       const Access readers = meshes_.store().mesh_access(rec.id).value_or(Access{rec.owner});
                       meshes_.store().remove_mesh(rec.id);
                       if (on_event) on_event({{"type", "mesh_deleted"}, {"mesh_id", rec.id}}, readers);
                       HttpResponse r;
                       r.status = 204;
                       r.content_type.clear();
                       return r;
                     }});
  routes_.push_back({"GET", "/api/v1/meshes/{id}/download", "Download a mesh in a format",
                     {{"format", "obj, off, ply, stl, glb or drc (default: the uploaded format)"}},
                     [this, find](const Params& p, const HttpRequest& req, const Caller& caller) {
                       const MeshRecord rec = find(p, caller);
                       const auto q = split_target(req.target).second;
                       const auto f = q.find("format");
                       const std::string format = f == q.end() ? rec.format : f->second;
                       HttpResponse r;
                       r.body = meshes_.download(rec, format);
                       r.content_type = content_type_of("." + format);
                       std::string stem = rec.name.substr(0, rec.name.find_last_of('.'));
                       for (char& c : stem)
                         if (c == '"' || c == '\\') c = '_';
                       r.headers.push_back({"Content-Disposition", "attachment; filename=\"" + stem + "." + format + "\""});
                       return r;
                     }});
  routes_.push_back({"GET", "/api/v1/meshes/{id}/textures/{n}", "A texture image of a mesh (n: its index in the mesh's textures)", {},
                     [this, find](const Params& p, const HttpRequest&, const Caller& caller) {
                       const MeshRecord rec = find(p, caller);
                       const json textures = material_of(rec)["textures"];
                       const std::string& n = p.at("n");
                       const bool number = !n.empty() && n.size() <= 3 && n.find_first_not_of("0123456789") == std::string::npos;
                       const std::size_t k = number ? std::stoul(n) : textures.size();
                       if (k >= textures.size())
                         throw std::out_of_range("mesh " + rec.id + " has no texture '" + n + "' (it has " +
                                                 std::to_string(textures.size()) + ")");
                       HttpResponse r;
                       r.body = meshes_.store().read_texture(rec, k);
                       r.content_type = textures[k].value("mime", "application/octet-stream");
                       return r;
                     }});
  // Offscreen renders (algorithms/render): a PNG of one mesh, for scripts and the viewer's thumbnails.
  routes_.push_back({"GET", "/api/v1/meshes/{id}/render.png", "A picture of the mesh from the EGL offscreen renderer",
                     {{"mode", "points, wireframe, flat, smooth (default) or toon"},
                      {"width", "image width in pixels, 1..8192 (default 800)"},
                      {"height", "image height in pixels, 1..8192 (default 600)"},
                      {"azimuth", "camera azimuth around +y in degrees (default 30)"},
                      {"elevation", "camera elevation in degrees, -90..90 (default 20)"},
                      {"projection", "perspective (default) or orthographic"},
                      {"field", "a scalar-field artifact to colour by: JOB_ID/NAME, or NAME for the newest done job on this mesh"}},
                     [this, find](const Params& p, const HttpRequest& req, const Caller& caller) {
                       return render_png(find(p, caller), req, caller);
                     }});
  routes_.push_back({"POST", "/api/v1/meshes/{id}/share",
                     "Share a mesh (its owner or an admin): {\"users\":[NAME,...]} and/or {\"everyone\":true}; answers who reads it", {},
                     [this, find_owned](const Params& p, const HttpRequest& req, const Caller& caller) {
                       return share("mesh", p.at("id"), find_owned(p, caller).owner, req, true);
                     },
                     false});
  routes_.push_back({"POST", "/api/v1/meshes/{id}/unshare", "Stop sharing a mesh: the same body as share", {},
                     [this, find_owned](const Params& p, const HttpRequest& req, const Caller& caller) {
                       return share("mesh", p.at("id"), find_owned(p, caller).owner, req, false);
                     },
                     false});
  // Algorithms and jobs (protocol/API.md): run in worker processes by the JobScheduler.
  auto jobs = [this]() -> JobScheduler& {
    if (!config_.jobs) throw std::runtime_error("this server runs no jobs");
    return *config_.jobs;
  };
  routes_.push_back({"GET", "/api/v1/algorithms", "The algorithms a job may run, with a JSON Schema of their parameters", {},
                     [jobs](const Params&, const HttpRequest&, const Caller&) { return json_response(200, jobs().algorithms_json()); },
                     false});
  routes_.push_back({"POST", "/api/v1/jobs", "Submit a job: {\"algorithm\",\"inputs\":{\"mesh\":id or {\"job\":id,\"artifact\":name},...},\"params\":{...}}", {},
                     [this, jobs](const Params&, const HttpRequest& req, const Caller& caller) {
                       const json body = parse_json_or_discarded(req.body);
                       if (body.is_discarded()) return error_response(400, "bad_request", "the body is not JSON");
                       json job;
                       std::vector<std::string> new_meshes;
                       try {
                         job = jobs().submit(body, caller, &new_meshes);
                       } catch (const InvalidInput& e) {
                         return error_response(400, "bad_request", e.what());
                       }
                       // A chained job's input mesh is stored: the mesh lists show it.
                       for (const auto& id : new_meshes)
                         if (const auto rec = meshes_.store().get_mesh(id); rec && on_event)
                           on_event({{"type", "mesh_added"}, {"mesh", mesh_json(*rec)}}, {rec->owner});
                       HttpResponse r = json_response(201, job);
                       r.headers.push_back({"Location", "/api/v1/jobs/" + job["id"].get<std::string>()});
                       return r;
                     },
                     false});
  routes_.push_back({"GET", "/api/v1/jobs", "List the jobs, oldest first", {},
                     [jobs](const Params&, const HttpRequest&, const Caller& caller) { return json_response(200, jobs().list(caller)); },
                     false});
  routes_.push_back({"GET", "/api/v1/jobs/{id}", "One job: state, progress, artifacts", {},
                     [jobs](const Params& p, const HttpRequest&, const Caller& caller) {
                       const auto job = jobs().get(p.at("id"), caller);
                       if (!job) return error_response(404, "not_found", "no job with id '" + p.at("id") + "'");
                       return json_response(200, *job);
                     },
                     false});
  routes_.push_back({"DELETE", "/api/v1/jobs/{id}", "Cancel a queued or running job; answers the job", {},
                     [jobs](const Params& p, const HttpRequest&, const Caller& caller) {
                       const auto job = jobs().cancel(p.at("id"), caller);
                       if (!job) return error_response(404, "not_found", "no job with id '" + p.at("id") + "'");
                       return json_response(200, *job);
                     },
                     false});
  routes_.push_back({"GET", "/api/v1/jobs/{id}/artifacts/{name}", "An artifact of a done job in a format",
                     {{"format", "scalar field: json (default), f32, txt, csv, ply; mesh: ply (default) or any writable mesh format; metrics: json; text: txt; animation: frames"}},
                     [jobs](const Params& p, const HttpRequest& req, const Caller& caller) {
                       const auto q = split_target(req.target).second;
                       const auto f = q.find("format");
                       ArtifactBytes a;
                       try {
                         a = jobs().artifact(p.at("id"), p.at("name"), f == q.end() ? "" : f->second, caller);
                       } catch (const InvalidInput& e) {
                         return error_response(400, "bad_request", e.what());
                       }
                       HttpResponse r;
                       r.body = std::move(a.bytes);
                       r.content_type = a.content_type;
                       r.headers.push_back({"Content-Disposition", "attachment; filename=\"" + a.file_name + "\""});
                       return r;
                     }});
  // A job shared is its state and artifacts, read-only.
  auto job_owner = [jobs](const Params& p, const Caller& caller) {
    const Access a = jobs().access(p.at("id"), caller);
    if (!a.owned_by(caller)) throw Forbidden("job " + p.at("id") + " is " + a.owner + "'s: only its owner changes it");
    return a.owner;
  };
  routes_.push_back({"POST", "/api/v1/jobs/{id}/share",
                     "Share a job and its artifacts (its owner or an admin): the same body as a mesh's share", {},
                     [this, job_owner](const Params& p, const HttpRequest& req, const Caller& caller) {
                       return share("job", p.at("id"), job_owner(p, caller), req, true);
                     },
                     false});
  routes_.push_back({"POST", "/api/v1/jobs/{id}/unshare", "Stop sharing a job", {},
                     [this, job_owner](const Params& p, const HttpRequest& req, const Caller& caller) {
                       return share("job", p.at("id"), job_owner(p, caller), req, false);
                     },
                     false});
  // A job's worker on a node without the data directory: its own token
  // (Authorization: Bearer), not a user's, reads its inputs and writes its results.
  auto worker_token = [](const HttpRequest& req) {
    return starts_with_nocase(req.authorization, "Bearer ") ? std::string_view(req.authorization).substr(7)
                                                             : std::string_view();
  };
  routes_.push_back({"GET", "/api/v1/worker/jobs/{id}/spec", "A running job's job.json, for its worker (the job's token)", {},
                     [jobs, worker_token](const Params& p, const HttpRequest& req, const Caller&) {
                       HttpResponse r;
                       r.body = jobs().worker_spec(p.at("id"), worker_token(req));
                       return r;
                     }});
  routes_.push_back({"GET", "/api/v1/worker/jobs/{id}/inputs/{name}", "An input file of a running job, for its worker (the job's token)", {},
                     [jobs, worker_token](const Params& p, const HttpRequest& req, const Caller&) {
                       HttpResponse r;
                       r.body = read_file_bytes(jobs().worker_input(p.at("id"), worker_token(req), p.at("name")), std::uint64_t(1) << 40);
                       r.content_type = "application/octet-stream";
                       return r;
                     }});
  routes_.push_back({"PUT", "/api/v1/worker/jobs/{id}/files/{name}", "A result file of a running job, from its worker (the job's token)", {},
                     [jobs, worker_token](const Params& p, const HttpRequest& req, const Caller&) {
                       jobs().worker_put(p.at("id"), worker_token(req), p.at("name"), req.body);
                       return json_response(200, json{{"stored", p.at("name")}, {"bytes", req.body.size()}});
                     }});
  routes_.push_back({"POST", "/api/v1/worker/jobs/{id}/progress", "A running job's progress line (\"progress F STAGE\"), from its worker (the job's token)", {},
                     [jobs, worker_token](const Params& p, const HttpRequest& req, const Caller&) {
                       jobs().worker_progress(p.at("id"), worker_token(req), req.body);
                       return json_response(200, json{{"progress", true}});
                     }});
  routes_.push_back({"GET", "/api/v1/openapi.json", "This API's OpenAPI 3 document", {},
                     [this](const Params&, const HttpRequest&, const Caller&) { return json_response(200, openapi()); },
                     false});
}

namespace {

HttpResponse bad_parameter(const std::string& name, const std::string& detail) {
  return json_response(400, json{{"error", "bad_request"}, {"detail", detail}, {"parameter", name}});
}

}  // namespace

HttpResponse Router::render_png(const MeshRecord& rec, const HttpRequest& req, const Caller& caller) const {
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
    if (q.count("field")) field = resolve_field(rec, q.at("field"), caller);
  } catch (const BadParameter& e) {
    return bad_parameter(e.parameter, e.what());
  }
  const std::shared_ptr<const Mesh> mesh = meshes_.mesh(rec);
  if (field) {
    try {
      field->check_matches(*mesh);
    } catch (const InvalidInput& e) {
      return bad_parameter("field", std::string("parameter 'field': ") + e.what());
    }
  }
  HttpResponse r;
  try {
    r.body = renders_->png(*mesh, field ? &*field : nullptr, params);
  } catch (const InvalidInput&) {
    throw;
  } catch (const Error& e) {
    return error_response(503, "render_unavailable", e.what());
  }
  r.content_type = "image/png";
  r.headers.push_back({"Cache-Control", "private, max-age=60"});
  return r;
}

HttpResponse Router::share(const std::string& kind, const std::string& id, const std::string& owner, const HttpRequest& req,
                           bool add) const {
  const json body = parse_json_or_discarded(req.body);
  const char* shape = "the body is {\"users\": [NAME, ...]} and/or {\"everyone\": true}";
  if (!body.is_object()) return error_response(400, "bad_request", shape);
  std::vector<std::string> users;
  const json names = body.value("users", json::array());
  if (!names.is_array()) return error_response(400, "bad_request", shape);
  for (const auto& n : names) {
    if (!n.is_string()) return error_response(400, "bad_request", shape);
    if (!meshes_.store().get_user(n)) return error_response(400, "bad_request", "no user '" + n.get<std::string>() + "'");
    users.push_back(n);
  }
  const json everyone = body.value("everyone", json(false));
  if (!everyone.is_boolean()) return error_response(400, "bad_request", shape);
  if (everyone.get<bool>()) users.push_back(kEveryone);
  if (users.empty()) return error_response(400, "bad_request", shape);
  meshes_.store().set_shared(kind, id, users, add);
  const Access a = meshes_.store().access(kind, id, owner);
  return json_response(200, {{"id", id}, {"owner", a.owner}, {"users", a.readers}, {"everyone", a.everyone}});
}

ScalarField Router::resolve_field(const MeshRecord& rec, const std::string& spec, const Caller& caller) const {
  auto bad = [](const std::string& why) { return BadParameter("field", "parameter 'field': " + why); };
  if (!config_.jobs) throw bad("this server runs no jobs, so it has no fields");
  std::string job_id, name;
  if (const std::size_t slash = spec.find('/'); slash != std::string::npos) {
    job_id = spec.substr(0, slash);
    name = spec.substr(slash + 1);
  } else {
    name = spec;
    // The newest done job on this mesh with an artifact of that name.
    const json list = config_.jobs->list(caller);
    const json& jobs = list.is_object() && list.contains("jobs") ? list["jobs"] : list;
    for (auto it = jobs.rbegin(); it != jobs.rend(); ++it) {
      const json& j = *it;
      if (j.value("state", "") != "done") continue;
      const json inputs = j.value("inputs", json::object());
      if (!inputs.contains("mesh") || !inputs["mesh"].is_string() || inputs["mesh"].get<std::string>() != rec.id) continue;
      for (const auto& a : j.value("artifacts", json::array()))
        if (a.value("name", "") == name && a.value("kind", "") == "scalar_field") job_id = j.value("id", "");
      if (!job_id.empty()) break;
    }
    if (job_id.empty()) throw bad("no done job on mesh " + rec.id + " has a scalar field '" + name + "'");
  }
  if (job_id.empty() || name.empty()) throw bad("'" + spec + "' is not JOB_ID/NAME or NAME");
  ArtifactBytes a;
  try {
    a = config_.jobs->artifact(job_id, name, "json", caller);
  } catch (const std::exception& e) {
    throw bad(e.what());
  }
  const json j = json::parse(a.bytes, nullptr, false);
  if (!j.is_object() || !j.contains("values")) throw bad("artifact '" + name + "' of job " + job_id + " is not a scalar field");
  ScalarField f;
  f.name = j.value("name", name);
  f.location = j.value("location", "vertex") == "face" ? Location::face : Location::vertex;
  const std::string hint = j.value("hint", "standard");
  f.hint = hint == "symmetric" ? ColorHint::symmetric : hint == "magnitude" ? ColorHint::magnitude
           : hint == "categorical" ? ColorHint::categorical : ColorHint::standard;
  for (const auto& v : j["values"]) f.values.push_back(v.is_number() ? v.get<float>() : NAN);
  return f;
}

bool Router::is_heavy(const HttpRequest& req) const {
  const std::string path = split_target(req.target).first;
  std::map<std::string, std::string> params;
  for (const Route& r : routes_)
    if (r.method == req.method && match(r.pattern, path, params)) return r.heavy;
  return true;
}

HttpResponse Router::handle(const HttpRequest& req) const {
  const auto t0 = std::chrono::steady_clock::now();
  std::string route = "unmatched";
  HttpResponse r = dispatch(req, route);
  if (config_.metrics)
    config_.metrics->request(route, req.method, r.status,
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return r;
}

HttpResponse Router::dispatch(const HttpRequest& req, std::string& route) const {
  const auto [path, query] = split_target(req.target);
  // The web client's files are public (it asks for a token); the API and the metrics are not.
  std::optional<Caller> caller;
  // A worker's routes take its job's token instead (JobScheduler::worker_*).
  if ((path.starts_with("/api/") || path == "/metrics") && !path.starts_with("/api/v1/worker/")) {
    caller = auth_.authenticate(req.authorization);
    if (!caller) {
      HttpResponse r = error_response(401, "unauthorized", req.authorization.empty()
                                                               ? "this server needs a token: Authorization: Bearer TOKEN"
                                                               : "the token is wrong or was revoked");
      r.headers.push_back({"WWW-Authenticate", "Bearer"});
      return r;
    }
  }
  bool path_known = false;
  for (const Route& r : routes_) {
    std::map<std::string, std::string> params;
    if (!match(r.pattern, path, params)) continue;
    path_known = true;
    if (r.method != req.method) continue;
    route = r.pattern;
    for (const auto& [name, value] : params)
      if (!valid_path_param(value))
        return error_response(400, "bad_request", "'" + name + "' is not a valid " + name + ": letters, digits, '_', '.' or '-'");
    try {
      return r.handler(params, req, caller.value_or(Caller::local()));
    } catch (const WorkerTokenRefused& e) {
      HttpResponse res = error_response(401, "unauthorized", e.what());
      res.headers.push_back({"WWW-Authenticate", "Bearer"});
      return res;
    } catch (const QuotaExceeded& e) {
      HttpResponse res = json_response(e.status, json{{"error", e.code}, {"detail", e.what()}, {"limit", e.limit}, {"used", e.used}});
      if (e.status == 429) res.headers.push_back({"Retry-After", std::to_string(e.retry_after_s)});
      return res;
    } catch (const Forbidden& e) {
      return error_response(403, "forbidden", e.what());
    } catch (const UnsupportedFormat& e) {
      return error_response(400, "unsupported_format", e.what());
    } catch (const TooLarge& e) {
      return error_response(413, "payload_too_large", e.what());
    } catch (const InvalidInput& e) {
      return error_response(400, "invalid_mesh", e.what());
    } catch (const std::out_of_range& e) {
      return error_response(404, "not_found", e.what());
    } catch (const DiskFull&) {
      return error_response(507, "insufficient_storage",
                            "the server's storage is full: nothing was stored; retry once space is freed");
    } catch (const std::exception& e) {
      return error_response(500, "internal", e.what());
    }
  }
  if (path_known) return error_response(405, "method_not_allowed", req.method + " is not allowed on " + path);
  if (path.starts_with("/api/")) return error_response(404, "not_found", "no route " + req.method + " " + path);
  if (req.method != "GET" && req.method != "HEAD") return error_response(405, "method_not_allowed", "only GET serves files");
  route = "static";
  return serve_static(path);
}

HttpResponse Router::serve_static(const std::string& path) const {
  if (config_.static_dir.empty()) return error_response(404, "not_found", "no web client is served (--static-dir)");
  if (path.find("..") != std::string::npos || path.find('\0') != std::string::npos || path.empty() || path[0] != '/')
    return error_response(400, "bad_request", "bad path");
  // "//etc/passwd" (or "/%2Fetc...") leaves an absolute path after the first
  // '/', and dir / absolute is the absolute path itself: refuse it.
  const fs::path relative = path.substr(1);
  if (relative.has_root_path()) return error_response(400, "bad_request", "bad path");
  fs::path file = config_.static_dir / relative;
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

json Router::openapi() const {
  json paths = json::object();
  for (const Route& r : routes_) {
    json op{{"summary", r.summary}, {"responses", json::object()}};
    json params = json::array();
    for (std::size_t p = r.pattern.find('{'); p != std::string::npos; p = r.pattern.find('{', p + 1)) {
      const std::string name = r.pattern.substr(p + 1, r.pattern.find('}', p) - p - 1);
      params.push_back({{"name", name}, {"in", "path"}, {"required", true}, {"schema", {{"type", "string"}}}});
    }
    for (const auto& [name, help] : r.query)
      params.push_back({{"name", name}, {"in", "query"}, {"description", help}, {"schema", {{"type", "string"}}}});
    if (!params.empty()) op["parameters"] = params;
    const json error_ref = {{"description", "error"},
                            {"content", {{"application/json", {{"schema", {{"$ref", "#/components/schemas/Error"}}}}}}}};
    op["responses"]["200"] = {{"description", "success"}};
    const bool is_job = r.pattern.starts_with("/api/v1/jobs");
    const bool json_body = r.pattern != "/api/v1/meshes";  // every POST but the upload takes JSON
    if (r.method == "POST" && json_body) {
      op["requestBody"] = {{"content", {{"application/json", {{"schema", {{"type", "object"}}}}}}}};
      if (r.pattern == "/api/v1/jobs") {
        op["responses"].erase("200");
        op["responses"]["201"] = {{"description", "created"}};
        op["responses"]["413"] = error_ref;  // no room left under the storage quota
        op["responses"]["429"] = error_ref;  // the concurrent job limit
      } else {
        op["responses"]["403"] = error_ref;  // share, unshare: only the owner
      }
    } else if (r.method == "POST") {
      // The mesh file, or a zip of it with its MTL and images (README "Textured meshes").
      const json binary = {{"schema", {{"type", "string"}, {"format", "binary"}}}};
      op["requestBody"] = {{"content", {{"application/octet-stream", binary}, {"application/zip", binary}}}};
      op["responses"].erase("200");
      op["responses"]["201"] = {{"description", "created"}};
      op["responses"]["413"] = error_ref;
    }
    if (r.method == "DELETE" && !is_job) {
      op["responses"].erase("200");
      op["responses"]["204"] = {{"description", "deleted"}};
    }
    if (r.method == "DELETE") op["responses"]["403"] = error_ref;  // a shared item: only its owner
    op["responses"]["400"] = error_ref;
    if (r.pattern.find('{') != std::string::npos || (is_job && r.method == "POST")) op["responses"]["404"] = error_ref;
    op["responses"]["401"] = error_ref;
    std::string method = r.method;
    for (char& c : method) c = char(std::tolower(static_cast<unsigned char>(c)));
    paths[r.pattern][method] = op;
  }
  paths["/api/v1/ws"]["get"] = {{"summary", "WebSocket: JSON requests and events, binary mesh frames (protocol/API.md)"},
                                {"responses", {{"101", {{"description", "switching protocols"}}}}}};
  json error_schema = {{"type", "object"},
                       {"properties", {{"error", {{"type", "string"}}}, {"detail", {{"type", "string"}}}}},
                       {"required", {"error", "detail"}}};
  json doc;
  doc["openapi"] = "3.0.3";
  doc["info"] = {{"title", "CGView API"}, {"version", config_.version}};
  doc["paths"] = paths;
  doc["components"]["schemas"]["Error"] = error_schema;
  // On loopback a server needs no token; elsewhere (or with --auth required) every route does.
  doc["components"]["securitySchemes"]["bearer"] = {{"type", "http"}, {"scheme", "bearer"}};
  doc["security"] = json::array({{{"bearer", json::array()}}, json::object()});
  return doc;
}

}  // namespace cgview::server
