#include "job_json.h"

#include "artifacts/artifact_codec.h"

namespace cgview::protocol {

using nlohmann::json;

namespace {
constexpr const char* kNames[] = {"queued", "running", "done", "failed", "cancelled", "interrupted"};
}

const char* to_string(JobState state) { return kNames[int(state)]; }

std::optional<JobState> job_state_from(const std::string& name) {
  for (int i = 0; i < int(std::size(kNames)); ++i)
    if (name == kNames[i]) return JobState(i);
  return std::nullopt;
}

json job_json(const JobRecord& j) {
  auto opt = [](const std::string& s) { return s.empty() ? json(nullptr) : json(s); };
  json artifacts = j.artifacts.is_array() ? j.artifacts : json::array();
  for (auto& a : artifacts) {
    a.erase("file");
    // What ?format= takes for it, so that a client lists the downloads without a copy of the list.
    if (const ArtifactCodec* codec = a.is_object() ? artifact_codec(a.value("kind", "")) : nullptr) {
      json formats = json::array();
      for (const ArtifactFormat& f : codec->formats())
        if (f.served) formats.push_back(f.name);
      a["formats"] = std::move(formats);
    }
  }
  json out = {{"id", j.id},
              {"owner", j.owner},
              {"algorithm", j.algorithm},
              {"inputs", j.inputs},
              {"params", j.params},
              {"state", to_string(j.state)},
              {"progress", j.progress},
              {"stage", j.stage},
              {"error", opt(j.error)},
              {"cached", j.cached},
              {"created", j.created},
              {"started", opt(j.started)},
              {"finished", opt(j.finished)},
              {"artifacts", artifacts},
              {"warnings", j.warnings.is_array() ? j.warnings : json::array()}};
  if (!j.where.empty()) out["node"] = j.where;
  if (j.run_s > 0) out["run_s"] = j.run_s;
  // Which plugin it ran (never where its library lies on the server).
  if (j.plugin.is_object()) out["plugin"] = j.plugin.value("id", "");
  return out;
}

json progress_event(const JobRecord& j) {
  json job = {{"id", j.id}, {"state", to_string(j.state)}, {"progress", j.progress}, {"stage", j.stage}};
  if (!j.where.empty()) job["node"] = j.where;
  return {{"type", "job_progress"}, {"job", job}};
}

}  // namespace cgview::protocol
