#include "jobs/executor_registry.h"

#include "core/errors.h"
#include "jobs/local_executor.h"
#include "jobs/scheduler.h"
#include "jobs/slurm_executor.h"

namespace cgview::server {

const std::vector<ExecutorKind>& executor_kinds() {
  static const std::vector<ExecutorKind> kinds = {
      {LocalExecutor::kName, "this machine", "",
       [](const JobConfig& c) { return std::make_unique<LocalExecutor>(c.worker, c.max_workers, c.sandbox); }},
      {SlurmExecutor::kName, "a Slurm cluster", "slurm",
       [](const JobConfig& c) { return std::make_unique<SlurmExecutor>(c.slurm, c.worker, c.sandbox, c.memory_mb); }},
  };
  return kinds;
}

std::vector<std::pair<std::string, std::string>> executor_choices() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const ExecutorKind& k : executor_kinds()) out.emplace_back(k.name, k.name);
  return out;
}

std::string executor_help() {
  std::string out = "where jobs run: ";
  const auto& kinds = executor_kinds();
  for (std::size_t i = 0; i < kinds.size(); ++i)
    out += (i == 0                  ? ""
            : i + 1 == kinds.size() ? ", or "
                                    : ", ") +
           kinds[i].where + (kinds[i].section.empty() ? "" : " as the config's " + kinds[i].section + " section says");
  return out;
}

std::unique_ptr<Executor> make_executor(const JobConfig& config) {
  std::string names;
  for (const ExecutorKind& k : executor_kinds()) {
    if (k.name == config.executor) return k.make(config);
    names += (names.empty() ? "" : " or ") + k.name;
  }
  throw InvalidInput("executor '" + config.executor + "': it is " + names);
}

}  // namespace cgview::server
