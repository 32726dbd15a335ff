// The executors, by name: what `executor` (the setting) may be, the help it
// shows, the config file's section each reads, and how each is made.  A new
// executor is its class on ExecutorBase (executor.h), one line in
// executor_registry.cpp and, if it has settings, their struct in JobConfig
// (scheduler.h; as slurm_config.h's) and their section in settings.h.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "jobs/executor.h"

namespace cgview::server {

struct JobConfig;

struct ExecutorKind {
  std::string name;     // the setting's value, stored with each job it runs
  std::string where;    // where its jobs run, for --help ("this machine")
  std::string section;  // the config file's section of its settings ("": none)
  std::function<std::unique_ptr<Executor>(const JobConfig&)> make;  // throws InvalidInput
};

// Every executor, the default ("local") first.
const std::vector<ExecutorKind>& executor_kinds();

// The setting's choices (name -> name) and its help, for settings.h.
std::vector<std::pair<std::string, std::string>> executor_choices();
std::string executor_help();

// The executor `config.executor` names; throws InvalidInput for a name no
// executor has, or as its factory does.
std::unique_ptr<Executor> make_executor(const JobConfig& config);

}  // namespace cgview::server
