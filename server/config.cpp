#include "config.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "auth.h"
#include "core/errors.h"
#include "io/parse_json.h"

namespace cgview::server {

using nlohmann::json;

namespace {

[[noreturn]] void bad(const std::string& key, const std::string& why) { throw std::invalid_argument(key + ": " + why); }

std::int64_t integer(const json& v, const std::string& key, std::int64_t lo, std::int64_t hi) {
  if (!v.is_number_integer() || v.get<std::int64_t>() < lo || v.get<std::int64_t>() > hi)
    bad(key, "must be an integer " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + v.dump());
  return v.get<std::int64_t>();
}

std::string text(const json& v, const std::string& key) {
  if (!v.is_string()) bad(key, "must be a string, got " + v.dump());
  return v.get<std::string>();
}

const json& object(const json& v, const std::string& key) {
  if (!v.is_object()) bad(key, "must be an object, got " + v.dump());
  return v;
}

// The "server" section: ServerConfig's settings by the names of their flags.
using Setter = std::function<void(const json&, const std::string& key, ServerConfig&)>;
const std::map<std::string, Setter>& server_keys() {
  static const std::map<std::string, Setter> keys = {
      {"host", [](const json& v, const std::string& k, ServerConfig& c) { c.host = text(v, k); }},
      {"port", [](const json& v, const std::string& k,
                  ServerConfig& c) { c.port = static_cast<unsigned short>(integer(v, k, 0, 65535)); }},
      {"static_dir", [](const json& v, const std::string& k, ServerConfig& c) { c.static_dir = text(v, k); }},
      {"max_upload_mb", [](const json& v, const std::string& k,
                           ServerConfig& c) { c.max_upload_bytes = std::size_t(integer(v, k, 1, 1 << 20)) << 20; }},
      {"workers", [](const json& v, const std::string& k, ServerConfig& c) { c.workers = int(integer(v, k, 1, 256)); }},
      {"ws_chunk_kb", [](const json& v, const std::string& k,
                         ServerConfig& c) { c.chunk_bytes = std::size_t(integer(v, k, 1, 16 * 1024 - 1)) << 10; }},
      {"auth",
       [](const json& v, const std::string& k, ServerConfig& c) {
         const std::string m = text(v, k);
         if (m != "auto" && m != "required") bad(k, "is \"auto\" or \"required\", got " + v.dump());
         c.auth_required = m == "required";
       }},
      {"gl_platform", [](const json& v, const std::string& k,
                         ServerConfig& c) { c.gl_platform = render::parse_gl_platform(text(v, k), k.c_str()); }},
      {"worker", [](const json& v, const std::string& k, ServerConfig& c) { c.jobs.worker = text(v, k); }},
      {"job_workers",
       [](const json& v, const std::string& k, ServerConfig& c) { c.jobs.max_workers = int(integer(v, k, 1, 1024)); }},
      {"job_timeout_s", [](const json& v, const std::string& k,
                           ServerConfig& c) { c.jobs.timeout_s = double(integer(v, k, 0, 100000000)); }},
      {"job_memory_mb", [](const json& v, const std::string& k,
                           ServerConfig& c) { c.jobs.memory_mb = std::size_t(integer(v, k, 0, 1 << 24)); }},
      {"reader", [](const json& v, const std::string& k, ServerConfig& c) { c.reader = text(v, k); }},
      {"upload_timeout_s", [](const json& v, const std::string& k,
                              ServerConfig& c) { c.upload_timeout_s = double(integer(v, k, 1, 86400)); }},
      {"max_header_kb", [](const json& v, const std::string& k,
                           ServerConfig& c) { c.max_header_bytes = std::size_t(integer(v, k, 1, 1 << 20)) << 10; }},
      {"max_ws_message_kb",
       [](const json& v, const std::string& k, ServerConfig& c) {
         c.max_ws_message_bytes = std::size_t(integer(v, k, 1, 1 << 20)) << 10;
       }},
      {"request_timeout_s", [](const json& v, const std::string& k,
                               ServerConfig& c) { c.request_timeout_s = double(integer(v, k, 1, 86400)); }},
      {"min_body_rate_kb", [](const json& v, const std::string& k,
                              ServerConfig& c) { c.min_body_rate = double(integer(v, k, 1, 1 << 20)) * 1024; }},
      {"idle_timeout_s", [](const json& v, const std::string& k,
                            ServerConfig& c) { c.idle_timeout_s = double(integer(v, k, 1, 86400)); }},
      {"ws_idle_timeout_s", [](const json& v, const std::string& k,
                               ServerConfig& c) { c.ws_idle_timeout_s = double(integer(v, k, 2, 86400)); }},
      {"max_connections_per_ip", [](const json& v, const std::string& k,
                                    ServerConfig& c) { c.max_connections_per_ip = int(integer(v, k, 0, 1 << 20)); }},
      {"ws_auth_timeout_s", [](const json& v, const std::string& k,
                               ServerConfig& c) { c.ws_auth_timeout_s = double(integer(v, k, 1, 3600)); }},
      // {"rate": R, "burst": B} (requests per second per token; rate 0: no limit).
      {"rate_limit",
       [](const json& v, const std::string& k, ServerConfig& c) {
         bool burst = false;
         for (const auto& [key, x] : object(v, k).items()) {
           if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < (key == "burst" ? 1 : 0))
             bad(k + "." + key, "must be a number (rate >= 0, burst >= 1), got " + x.dump());
           if (key == "rate") c.rate_per_s = x.get<double>();
           else if (key == "burst") c.rate_burst = x.get<double>(), burst = true;
           else bad(k + "." + key, "unknown key (rate_limit has rate and burst)");
         }
         if (!burst) c.rate_burst = std::max(1.0, c.rate_per_s * 4);  // as --rate-limit R
       }},
      {"tls_cert", [](const json& v, const std::string& k, ServerConfig& c) { c.tls_cert = text(v, k); }},
      {"tls_key", [](const json& v, const std::string& k, ServerConfig& c) { c.tls_key = text(v, k); }},
      {"job_cpus",
       [](const json& v, const std::string& k, ServerConfig& c) { c.jobs.cpus = int(integer(v, k, 1, 1024)); }},
      {"executor",
       [](const json& v, const std::string& k, ServerConfig& c) {
         const std::string e = text(v, k);
         if (e != "local" && e != "slurm") bad(k, "is \"local\" or \"slurm\", got " + v.dump());
         c.jobs.executor = e;
       }},
      {"on_restart",
       [](const json& v, const std::string& k, ServerConfig& c) {
         const std::string m = text(v, k);
         if (m != "requeue" && m != "interrupt") bad(k, "is \"requeue\" or \"interrupt\", got " + v.dump());
         c.jobs.requeue_on_restart = m == "requeue";
       }},
  };
  return keys;
}

bool boolean(const json& v, const std::string& key) {
  if (!v.is_boolean()) bad(key, "must be true or false, got " + v.dump());
  return v.get<bool>();
}

// storage_mb: a number of MB (fractions allowed), or null (unlimited).
std::optional<std::uint64_t> storage(const json& v, const std::string& key) {
  if (v.is_null()) return std::nullopt;
  if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0 || v.get<double>() > 1e12)
    bad(key, "must be a number of MB >= 0, or null (unlimited), got " + v.dump());
  return std::uint64_t(std::llround(v.get<double>() * double(1 << 20)));
}

std::optional<int> jobs(const json& v, const std::string& key) {
  if (v.is_null()) return std::nullopt;
  return int(integer(v, key, 0, 1 << 20));
}

}  // namespace

void apply_config(const json& doc, ServerConfig& config) {
  object(doc, "the config");
  for (const auto& [section, body] : doc.items()) {
    if (section == "server") {
      for (const auto& [key, v] : object(body, section).items()) {
        const auto it = server_keys().find(key);
        if (it == server_keys().end()) {
          std::string known;
          for (const auto& [k, s] : server_keys()) known += (known.empty() ? "" : ", ") + k;
          bad("server." + key, "unknown key (the server section knows " + known + ")");
        }
        it->second(v, "server." + key, config);
      }
    } else if (section == "limits") {
      for (const auto& [key, v] : object(body, section).items()) {
        if (key == "storage_mb") config.jobs.quotas.defaults.storage_bytes = storage(v, "limits." + key);
        else if (key == "concurrent_jobs") config.jobs.quotas.defaults.concurrent_jobs = jobs(v, "limits." + key);
        else if (key == "plugins") config.jobs.quotas.defaults.plugins = boolean(v, "limits." + key);
        else bad("limits." + key, "unknown key (limits are storage_mb, concurrent_jobs and plugins)");
      }
    } else if (section == "users") {
      for (const auto& [name, limits] : object(body, section).items()) {
        const std::string where = "users." + name;
        if (name != "local" && !valid_user_name(name)) bad(where, "'" + name + "' is not a user name");
        UserOverride& o = config.jobs.quotas.users[name];
        for (const auto& [key, v] : object(limits, where).items()) {
          if (key == "storage_mb") o.storage_bytes = storage(v, where + "." + key);
          else if (key == "concurrent_jobs") o.concurrent_jobs = jobs(v, where + "." + key);
          else if (key == "plugins") o.plugins = boolean(v, where + "." + key);
          else bad(where + "." + key, "unknown key (a user's limits are storage_mb, concurrent_jobs and plugins)");
        }
      }
    } else if (section == "slurm") {
      SlurmConfig& sl = config.jobs.slurm;
      for (const auto& [key, v] : object(body, section).items()) {
        const std::string k = "slurm." + key;
        if (key == "partition") sl.partition = text(v, k);
        else if (key == "account") sl.account = text(v, k);
        else if (key == "qos") sl.qos = text(v, k);
        else if (key == "sbatch_args") {
          if (!v.is_array()) bad(k, "must be a list of strings, got " + v.dump());
          sl.sbatch_args.clear();
          for (const auto& a : v) sl.sbatch_args.push_back(text(a, k));
        } else if (key == "max_jobs") sl.max_jobs = int(integer(v, k, 1, 1000000));
        else if (key == "max_pending") sl.max_pending = int(integer(v, k, 1, 1000000));
        else if (key == "poll_s") {
          if (!v.is_number() || !(v.get<double>() >= 0.05) || v.get<double>() > 3600)
            bad(k, "must be a number of seconds 0.05..3600, got " + v.dump());
          sl.poll_s = v.get<double>();
        } else if (key == "shared_data") {
          if (!v.is_boolean()) bad(k, "must be true or false, got " + v.dump());
          sl.shared_data = v.get<bool>();
        } else if (key == "server_url") sl.server_url = text(v, k);
        else if (key == "on_lost") {
          const std::string m = text(v, k);
          if (m != "requeue" && m != "fail") bad(k, "is \"requeue\" or \"fail\", got " + v.dump());
          sl.requeue_lost = m == "requeue";
        } else if (key == "worker") sl.worker = text(v, k);
        else if (key == "sandbox") {
          if (!v.is_boolean()) bad(k, "must be true or false, got " + v.dump());
          sl.sandbox = v.get<bool>();
        } else
          bad(k,
              "unknown key (the slurm section knows partition, account, qos, sbatch_args, max_jobs, max_pending, "
              "poll_s, shared_data, server_url, on_lost, worker, sandbox)");
      }
    } else if (section == "sandbox") {
      SandboxConfig& sb = config.sandbox;
      for (const auto& [key, v] : object(body, section).items()) {
        const std::string k = "sandbox." + key;
        if (key == "mode") {
          sb.mode = text(v, k);
          if (sb.mode != "auto" && sb.mode != "required" && sb.mode != "off")
            bad(k, "is \"auto\", \"required\" or \"off\", got " + v.dump());
        } else if (key == "processes") sb.processes = int(integer(v, k, 8, 1 << 20));
        else if (key == "file_mb") sb.file_mb = std::size_t(integer(v, k, 1, 1LL << 30));
        else if (key == "hidden") {
          if (!v.is_array()) bad(k, "must be a list of paths, got " + v.dump());
          for (const auto& h : v) sb.hidden.push_back(text(h, k));
        } else if (key == "plugins_without_sandbox") config.plugins_without_sandbox = boolean(v, k);
        else
          bad(k, "unknown key (the sandbox section knows mode, processes, file_mb, hidden, plugins_without_sandbox)");
      }
    } else {
      bad(section, "unknown key (the sections are server, limits, users, slurm and sandbox)");
    }
  }
}

void load_config_file(const std::filesystem::path& file, ServerConfig& config) {
  std::ifstream f(file, std::ios::binary);
  if (!f) throw std::invalid_argument(file.string() + ": cannot read the config file");
  std::stringstream s;
  s << f.rdbuf();
  json doc;
  try {
    doc = parse_json(s.str(), file.string());
  } catch (const json::parse_error& e) {
    throw std::invalid_argument(file.string() + ": not JSON: " + e.what());
  } catch (const InvalidInput& e) {
    throw std::invalid_argument(e.what());
  }
  try {
    apply_config(doc, config);
  } catch (const std::exception& e) {
    throw std::invalid_argument(file.string() + ": " + e.what());
  }
}

}  // namespace cgview::server
