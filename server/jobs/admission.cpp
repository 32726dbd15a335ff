#include "jobs/admission.h"

#include <cstdio>
#include <optional>

#include "algorithm_json.h"
#include "core/errors.h"
#include "quota.h"
#include "registry/registry.h"
#include "upload_read.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json value_json(const ParamValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

}  // namespace

Admission::Admission(MeshService& meshes, const fs::path& worker) : meshes_(meshes) {
  // What the worker can run (the test worker has a few more, hidden).
  std::string cmd = "'";
  cmd += worker.string();
  cmd += "' --list";
  std::string text;
  if (FILE* p = ::popen(cmd.c_str(), "r")) {
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) text.append(buf, n);
    ::pclose(p);
  }
  const json list = json::parse(text, nullptr, false);
  if (list.is_array()) {
    for (const auto& a : list)
      if (a.is_object() && a.contains("name")) algorithms_[a["name"].get<std::string>()] = a;
  } else {
    // Serve meshes anyway; jobs will fail with the reason.
    std::fprintf(stderr, "cgview-server: warning: cannot run the job worker %s (--worker); jobs will fail\n",
                 worker.c_str());
    for (const auto& [name, a] : algorithms()) algorithms_[name] = protocol::to_json(a);
  }
}

json Admission::algorithms_json() const {
  json list = json::array();
  for (const auto& [name, a] : algorithms_)
    if (a.value("area", "") != "test" && a.value("area", "") != "system") list.push_back(a);
  return {{"algorithms", list}};
}

Job Admission::admit(const json& req, const Caller& caller, JobLookup& jobs, std::vector<std::string>* new_meshes,
                     bool system) const {
  const std::string& owner = caller.user;
  if (!req.is_object()) throw InvalidInput("the body must be a JSON object");
  if (!req.contains("algorithm") || !req["algorithm"].is_string()) throw InvalidInput("\"algorithm\" must be a string");
  const std::string algorithm = req["algorithm"].get<std::string>();
  std::optional<PluginAlgorithm> plugin;
  if (req.contains("plugin")) {
    if (!req["plugin"].is_string()) throw InvalidInput("\"plugin\" must be a plugin's id");
    if (!plugins_) throw InvalidInput("this server runs no plugins");
    plugin = plugins_(req["plugin"].get<std::string>(), algorithm, caller);
  } else if (!algorithms_.count(algorithm) || (!system && algorithms_.at(algorithm).value("area", "") == "system")) {
    throw std::out_of_range("no algorithm '" + algorithm + "'");
  }
  // Each input the algorithm declares is a stored mesh: its id, or an earlier
  // job's output mesh {"job": id, "artifact": name}.
  const json inputs = req.value("inputs", json::object());
  // An algorithm that lists no inputs takes one mesh; one that lists none (an empty list) takes none.
  const json& described = plugin ? plugin->description : algorithms_.at(algorithm);
  json specs = described.value("inputs", json::array({{{"name", "mesh"}, {"kind", "mesh"}}}));
  const auto shape = [](const std::string& name) {
    return "\"inputs\" must be {\"" + name + "\": \"<mesh id>\"} or {\"" + name +
           "\": {\"job\": \"<job id>\", \"artifact\": \"<name>\"}}";
  };
  if (!inputs.is_object())
    throw InvalidInput(specs.empty() ? "\"inputs\" must be {}" : shape(specs[0].value("name", "mesh")));
  std::string names;
  for (const auto& spec : specs) names += (names.empty() ? "" : ", ") + spec.value("name", "");
  for (const auto& [name, v] : inputs.items()) {
    bool known = false;
    for (const auto& spec : specs) known = known || spec.value("name", "") == name;
    if (!known)
      throw InvalidInput("algorithm '" + algorithm + "' has no input '" + name + "' (it takes: " + names + ")");
  }
  json resolved = json::object();
  InputSummaries summaries;
  std::string mesh_id, input_shas;
  std::optional<MeshRecord> mesh;
  for (const auto& spec : specs) {
    const std::string name = spec.value("name", ""), kind = spec.value("kind", "mesh");
    // A point cloud is a stored mesh (an uploaded cloud is one with no faces;
    // a mesh's vertices are one), or an earlier job's points or mesh; any
    // other kind but a mesh is an earlier job's artifact of that kind.
    const bool points = kind == to_string(OutputKind::points);
    if ((kind != "mesh" && !points) || (points && inputs.contains(name) && inputs[name].is_object())) {
      if (!inputs.contains(name))
        throw InvalidInput("input '" + name + "' is missing: {\"" + name +
                           "\": {\"job\": \"<job id>\", \"artifact\": \"<name>\"}}");
      const json& v = inputs[name];
      if (!v.is_object() || !v.value("job", json()).is_string() || !v.value("artifact", json()).is_string())
        throw InvalidInput(points ? "input '" + name + "' is a point cloud: \"<mesh id>\" or {\"job\": \"<job id>\", " +
                                        "\"artifact\": \"<name>\"} of a points or mesh artifact"
                                  : "input '" + name + "' is a " + kind +
                                        ": {\"job\": \"<job id>\", \"artifact\": \"<name>\"}");
      try {
        (void)jobs.artifact_file(v["job"], v["artifact"], kind, caller);
      } catch (const InvalidInput& wrong_kind) {
        if (!points) throw;
        try {  // a points input takes a mesh artifact too; the error stays the one about points
          (void)jobs.artifact_file(v["job"], v["artifact"], "mesh", caller);
        } catch (const InvalidInput&) {
          throw wrong_kind;
        }
      }
      resolved[name] = {{"job", v["job"]}, {"artifact", v["artifact"]}};
      input_shas += "\n" + name + "=" + v["job"].get<std::string>() + "/" + v["artifact"].get<std::string>();
      continue;
    }
    if (!inputs.contains(name)) throw InvalidInput("input '" + name + "' is missing: " + shape(name));
    const json& v = inputs[name];
    std::string id;
    if (v.is_string()) {
      id = v.get<std::string>();
    } else if (v.is_object() && v.value("job", json()).is_string() && v.value("artifact", json()).is_string()) {
      // A chain: an earlier job's output mesh becomes a stored mesh (once, by
      // content) and the new job runs on it like on any other.
      const std::string from = v["job"], artifact_name = v["artifact"];
      const ExportedArtifact ply = jobs.artifact(from, artifact_name, "ply", caller);
      if (const auto known = meshes_.store().find_by_sha256(sha256_hex(ply.bytes), owner)) id = known->id;
      else {
        // Refused before it stores anything (even where the job would be a cache hit).
        jobs.check_job_count(caller);
        jobs.check_storage(caller, ply.bytes.size(), "the mesh of " + from + "/" + artifact_name);
        // The client's name for it ("elephant · simplify 1000"), else one after the job.
        std::string stored_as = from + "-" + artifact_name + ".ply";
        if (v.contains("name")) {
          if (!v["name"].is_string()) throw InvalidInput("input '" + name + "': \"name\" must be a string");
          stored_as = clean_upload_name(v["name"]);
        }
        id = meshes_.upload(stored_as, "ply", ply.bytes, owner).id;
        if (new_meshes) new_meshes->push_back(id);
      }
    } else {
      throw InvalidInput(shape(name));
    }
    const auto rec = meshes_.store().get_mesh(id, caller);
    if (!rec) throw std::out_of_range("no mesh with id '" + id + "'");
    resolved[name] = id;
    // What a precheck may know of it: the stored report's box and counts.
    const json report = json::parse(rec->report_json, nullptr, false);
    if (report.is_object()) {
      InputSummary& sum = summaries[name];
      sum.vertices = report.value("vertices", std::size_t(0));
      sum.faces = report.value("faces", std::size_t(0));
      if (!points && sum.faces == 0 && !spec.value("faceless", false))
        throw InvalidInput("input '" + name + "' (" + rec->name + ") is a point cloud of " +
                           std::to_string(sum.vertices) + " points and no faces: " + algorithm +
                           " needs a mesh with faces (mesh the cloud first, or run an algorithm that takes points)");
      const json box = report.value("bbox", json::object());
      if (box.contains("min") && box.contains("max") && box["min"].size() == 3 && box["max"].size() == 3 &&
          box["min"][0].is_number() && box["max"][0].is_number())
        for (int a = 0; a < 3; ++a) {
          sum.bbox.min[a] = box["min"][a].get<double>();
          sum.bbox.max[a] = box["max"][a].get<double>();
        }
    }
    if (!mesh) {
      mesh = rec;
      mesh_id = id;
    } else {
      input_shas += "\n" + name + "=" + rec->sha256;
    }
  }
  const json params_in = req.contains("params") ? req["params"] : json::object();
  // Canonical parameters: checked, every one present (defaults filled in).
  json canonical = json::object();
  const auto& registry = algorithms();
  // A plugin's algorithm is checked against its description (the server
  // never loads a user's code).
  std::optional<Algorithm> described_algorithm;
  if (plugin) described_algorithm = protocol::algorithm_from_json(plugin->description);
  const auto it = plugin ? registry.end() : registry.find(algorithm);
  const Algorithm* known = plugin ? &*described_algorithm : it != registry.end() ? &it->second : nullptr;
  if (known) {
    const auto values = protocol::params_from_json(*known, params_in);
    for (const ParamSpec& p : known->params) {
      const auto v = values.find(p.name);
      canonical[p.name] = value_json(v == values.end() ? p.default_value : v->second);
    }
    if (const auto in = summaries.find("mesh"); in != summaries.end())
      check_selections(known->params, values, in->second.vertices, in->second.faces);
    if (known->precheck) known->precheck(summaries, values);
  } else {
    // Only the worker knows it (a test algorithm): the worker checks.
    if (!params_in.is_null() && !params_in.is_object()) throw InvalidInput("\"params\" must be a JSON object");
    if (params_in.is_object()) canonical = params_in;
  }
  Job j;
  j.owner = owner;
  j.algorithm = algorithm;
  j.mesh_id = mesh_id;
  j.mesh_sha = mesh ? mesh->sha256 : "";
  j.inputs = resolved;
  j.params = canonical;
  // A one-mesh job keeps the key it always had (its cached results stay valid).
  // A plugin's job is keyed by its library's content too: a rebuilt plugin runs again.
  if (plugin) {
    j.plugin = {{"id", plugin->plugin_id}, {"library", plugin->library}};
    input_shas += "\nplugin=" + plugin->library_sha;
  }
  j.cache_key =
      sha256_hex((mesh ? mesh->sha256 : std::string()) + input_shas + "\n" + algorithm + "\n" + canonical.dump());
  return j;
}

}  // namespace cgview::server
