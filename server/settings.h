// cgview-server's settings, each described once, as an algorithm's
// parameters are (algorithms/registry/registry.h): its key in the config
// file, its flag, its range, default and help.  The flags and the config
// file are read (config.h), --help and docs/DEPLOYMENT.md's settings tables
// are written, and the config fuzzer's dictionary is checked
// (tests/server/settings_test) from Settings::describe, so that they cannot
// drift.  A new setting is its field (ServerConfig, server.h) and one line
// here; its table in DEPLOYMENT.md is then pasted from the test's message.
//
// In the config file's "server" section every key is a flag too: "--" and
// the key with '-' for '_' (max_upload_mb, --max-upload-mb).  Keys of the
// other sections have a flag only where it is given (sandbox.mode,
// --sandbox).  The field's initializer is the default; an integer whose name
// says its unit is held times `unit` (max_upload_mb: bytes, 1 << 20).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "jobs/executor_registry.h"
#include "server.h"

namespace cgview::server {

// Every member has an initializer, as in the registry's ParamInfo; a
// designated initializer names them in this order.
struct SettingInfo {
  std::string arg{};  // the value's name in --help ("DIR"); by default from its type
  double min = 0, max = 0;
  long long unit = 1;
  std::string help{};
  std::string default_text{};  // where the field's initial value does not say it ("the number of cores")
  std::string flag{};          // outside the server section; "--sandbox"
  bool file = true;            // false: a flag only, no key in the config file
};

// What cgview-server's flags and config file set: the server's config, and
// what main.cpp does besides.
struct Settings {
  ServerConfig server{};
  std::filesystem::path config_file{};  // "": DATA-DIR/config.json where it exists
  std::string samples = "default";

  template <class V>
  void describe(V& v) {
    ServerConfig& c = server;
    JobConfig& j = c.jobs;
    SlurmConfig& sl = c.jobs.slurm;
    v.section("server");
    v.heading("Settings (keys of the config file too, but --config, --data-dir and --samples; docs/DEPLOYMENT.md):");
    v.choice("auth", c.auth_required, {{"auto", false}, {"required", true}},
             {.help = "auto: tokens unless the address is loopback; required: every request carries one"});
    v.text("config", config_file,
           {.arg = "FILE",
            .help = "settings and per-user quotas, JSON; flags given here win over the file",
            .default_text = "DATA-DIR/config.json if there",
            .file = false});
    v.text("host", c.host, {.arg = "ADDR", .help = "address to listen on"});
    v.integer("port", c.port, {.min = 0, .max = 65535, .help = "port; 0 picks a free one"});
    v.text("data_dir", c.data_dir, {.arg = "DIR", .help = "where meshes are stored", .file = false});
    v.text("static_dir", c.static_dir,
           {.arg = "DIR", .help = "the built web client", .default_text = "web-client/dist of the source tree"});
    v.choice("samples", samples, {{"default", "default"}, {"all", "all"}, {"none", "none"}},
             {.help = "sample meshes to load at start", .file = false});
    v.integer("max_upload_mb", c.max_upload_bytes,
              {.min = 1, .max = 1 << 20, .unit = 1 << 20, .help = "largest accepted upload, a request's body"});

    v.heading("Limits (docs/DEPLOYMENT.md; over a limit: 431, 413, 408, 429 or 503 and the connection closed):");
    v.integer("max_header_kb", c.max_header_bytes,
              {.min = 1, .max = 1 << 20, .unit = 1 << 10, .help = "request line and headers"});
    v.integer("max_ws_message_kb", c.max_ws_message_bytes,
              {.min = 1, .max = 1 << 20, .unit = 1 << 10, .help = "a WebSocket message from a client"});
    v.integer("request_timeout_s", c.request_timeout_s,
              {.min = 1, .max = 86400, .help = "a request's headers must arrive within N s of its first byte"});
    v.integer("min_body_rate_kb", c.min_body_rate,
              {.min = 1, .max = 1 << 20, .unit = 1 << 10, .help = "then its body at N KB/s on average"});
    v.integer("idle_timeout_s", c.idle_timeout_s,
              {.min = 1, .max = 86400, .help = "a keep-alive connection with no request for N s is closed"});
    v.integer("ws_idle_timeout_s", c.ws_idle_timeout_s,
              {.min = 2, .max = 86400, .help = "a silent WebSocket is pinged at N/2 s, closed at N s without a pong"});
    v.integer(
        "ws_auth_timeout_s", c.ws_auth_timeout_s,
        {.min = 1, .max = 3600, .help = "a WebSocket not authenticated in N s is closed where tokens are needed"});
    v.integer("max_connections_per_ip", c.max_connections_per_ip,
              {.min = 0,
               .max = 1 << 20,
               .help = "open connections of one address; 0: no cap",
               .default_text = std::to_string(ServerConfig::kDefaultConnectionsPerIp) + " off loopback, none on it"});
    v.rate("rate_limit", c.rate_per_s, c.rate_burst,
           {.help = "requests per second per token, or per address without one (not the loopback local user), "
                    "in bursts of B; 0: none"});
    v.text("tls_cert", c.tls_cert,
           {.arg = "FILE",
            .help = "serve https:// and wss:// with this PEM certificate chain and --tls-key's key",
            .default_text = "none: plain HTTP, or TLS from a proxy, docker/Caddyfile"});
    v.text("tls_key", c.tls_key, {.arg = "FILE", .help = "the certificate's PEM private key", .default_text = "none"});

    v.heading("Geometry and jobs:");
    v.integer("workers", c.workers, {.min = 1, .max = 256, .help = "threads for geometry"});
    v.choice("gl_platform", c.gl_platform,
             {{"auto", render::GlPlatform::automatic},
              {"device", render::GlPlatform::device},
              {"surfaceless", render::GlPlatform::surfaceless}},
             {.help = "EGL platform for render.png: auto (a GPU device, else surfaceless llvmpipe), device or "
                      "surfaceless; also CGVIEW_GL_PLATFORM"});
    v.integer("ws_chunk_kb", c.chunk_bytes,
              {.min = 1, .max = 16 * 1024 - 1, .unit = 1 << 10, .help = "largest binary WebSocket chunk"});
    v.integer("preview_faces", c.preview.threshold_faces,
              {.min = 0, .max = 1LL << 40, .help = "meshes with more faces get a decimated preview first; 0: none"});
    v.integer("preview_target", c.preview.target_faces,
              {.min = 1, .max = 1LL << 40, .help = "the preview's most faces"});
    v.text("worker", j.worker,
           {.arg = "PATH", .help = "the job worker executable", .default_text = "cgview-worker beside this program"});
    v.integer("job_workers", j.max_workers,
              {.min = 1,
               .max = 1024,
               .help = "jobs run at once, each in its own process",
               .default_text = "the number of cores"});
    v.integer("job_timeout_s", j.timeout_s, {.min = 0, .max = 1e8, .help = "time limit of a job in seconds; 0: none"});
    v.integer("job_memory_mb", j.memory_mb,
              {.min = 0,
               .max = 1 << 24,
               .help = "address-space limit of a job's process in MB, also of the process that reads each upload "
                       "(over it: 413); 0: none"});
    v.integer("job_files", j.max_files,
              {.min = 1,
               .max = 1LL << 40,
               .help = "files, directories and links a running job may have in its directory, counted every 2 s; "
                       "over it the job is stopped"});
    v.text("reader", c.reader,
           {.arg = "PATH", .help = "the upload reader executable", .default_text = "cgview-read beside this program"});
    v.integer("upload_timeout_s", c.upload_timeout_s,
              {.min = 1, .max = 86400, .help = "time limit of reading one upload, in its own process; over it: 413"});
    v.choice("on_restart", j.requeue_on_restart, {{"requeue", true}, {"interrupt", false}},
             {.help = "jobs left queued or running by a previous run: run again, or marked interrupted"});
    v.choice("executor", j.executor, executor_choices(), {.help = executor_help()});
    v.integer("job_cpus", j.cpus, {.min = 1, .max = 1024, .help = "CPUs of a job, Slurm's --cpus-per-task"});
    v.text("plugin_dir", c.plugin_dir,
           {.arg = "DIR",
            .help = "the lab's plugins (*.cpp) for every user, rebuilt when a file changes",
            .default_text = "none"});

    v.section("sandbox");
    v.choice("mode", c.sandbox.mode, {{"auto", "auto"}, {"required", "required"}, {"off", "off"}},
             {.help = "each job's worker in bubblewrap: auto (where it starts), required (the server refuses to "
                      "start without it), off",
              .flag = "--sandbox"});
    v.integer("processes", c.sandbox.processes, {.min = 8, .max = 1 << 20, .help = "processes and threads of one job"});
    v.integer("file_mb", c.sandbox.file_mb, {.min = 1, .max = 1LL << 30, .help = "the largest file a job writes"});
    v.texts("hidden", c.sandbox.hidden,
            {.arg = "PATH",
             .help = "more paths no job may see; the TLS key and certificate and the config file are always hidden"});
    v.boolean("plugins_without_sandbox", c.plugins_without_sandbox,
              {.help = "users' plugins also where the sandbox cannot start (set it knowingly)"});

    v.section("slurm");
    v.text("partition", sl.partition, {.help = "sbatch's --partition", .default_text = "the cluster's"});
    v.text("account", sl.account, {.help = "sbatch's --account", .default_text = "the cluster's"});
    v.text("qos", sl.qos, {.help = "sbatch's --qos", .default_text = "the cluster's"});
    v.texts("sbatch_args", sl.sbatch_args, {.help = "more sbatch arguments, as they are"});
    v.integer(
        "max_jobs", sl.max_jobs,
        {.min = 1,
         .max = 1e6,
         .help = "CGView jobs in the cluster at once (pending or running); the rest wait in CGView's fair queue"});
    v.integer("max_pending", sl.max_pending,
              {.min = 1,
               .max = 1e6,
               .help = "CGView jobs pending in the cluster at once: Slurm sees one user (the server's), so jobs "
                       "handed over early would run in submission order; in CGView's queue owners take turns"});
    v.number("poll_s", sl.poll_s,
             {.min = 0.05, .max = 3600, .help = "seconds between squeue calls; one call covers every job"});
    v.boolean("shared_data", sl.shared_data, {.help = "the nodes see the data directory at the same path"});
    v.text("server_url", sl.server_url,
           {.arg = "URL",
            .help = "how a node reaches the server without a shared directory",
            .default_text = "the server's address"});
    v.choice("on_lost", sl.requeue_lost, {{"fail", false}, {"requeue", true}},
             {.help = "a job Slurm no longer knows: fail it with that reason, or requeue it"});
    v.text("worker", sl.worker,
           {.arg = "PATH", .help = "cgview-worker's path on the nodes", .default_text = "the server's --worker"});
    v.boolean(
        "sandbox", sl.sandbox,
        {.help = "with shared_data, workers start in the server's sandbox on the nodes too; they need bubblewrap"});
  }
};

}  // namespace cgview::server
