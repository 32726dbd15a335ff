#include "shared_state.h"

#include <boost/asio/ip/address.hpp>

#include <cmath>
#include <fstream>

#include "jobs/scheduler.h"
#include "plugins/plugin.h"

namespace cgview::server {

namespace ssl = boost::asio::ssl;
using nlohmann::json;

std::chrono::steady_clock::duration seconds(double s) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
}

namespace {

// The server's TLS context from the PEM files; throws naming the file at fault.
std::optional<ssl::context> tls_context(const ServerConfig& c) {
  if (c.tls_cert.empty() && c.tls_key.empty()) return std::nullopt;
  if (c.tls_cert.empty() || c.tls_key.empty())
    throw std::invalid_argument("TLS needs both a certificate and a key (--tls-cert, --tls-key)");
  for (const auto& f : {c.tls_cert, c.tls_key})
    if (!std::ifstream(f)) throw std::runtime_error("TLS: cannot read " + f.string());
  std::optional<ssl::context> ctx(std::in_place, ssl::context::tls_server);
  ctx->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                   ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
  try {
    ctx->use_certificate_chain_file(c.tls_cert.string());
  } catch (const std::exception& e) {
    throw std::runtime_error("TLS: " + c.tls_cert.string() + " is not a PEM certificate chain (" + e.what() + ")");
  }
  try {
    ctx->use_private_key_file(c.tls_key.string(), ssl::context::pem);
  } catch (const std::exception& e) {
    throw std::runtime_error("TLS: " + c.tls_key.string() + " is not the PEM private key of the certificate (" +
                             e.what() + ")");
  }
  return ctx;
}

// The sandbox, probed once; said at start when it cannot be used.
std::shared_ptr<const Sandbox> make_sandbox(const ServerConfig& c) {
  // The plugins' headers and precompiled header, wherever the build left them.
  SandboxConfig sc = c.sandbox;
  const PluginToolchain tc = default_toolchain();
  sc.visible.push_back(tc.include_dir);
  if (!tc.pch_dir.empty()) sc.visible.push_back(tc.pch_dir);
  // And CGView's programs (a worker wrapped by a script calls them).
  std::error_code ec;
  if (const auto self = std::filesystem::read_symlink("/proc/self/exe", ec); !ec)
    sc.visible.push_back(self.parent_path());
  auto s = std::make_shared<const Sandbox>(sc);
  if (!s->enabled()) {
    if (c.sandbox.mode == "required") throw std::runtime_error("the sandbox is required but " + s->why_not());
    std::fprintf(stderr, "cgview-server: warning: jobs run without a sandbox (%s); users' plugins are off%s\n",
                 s->why_not().c_str(),
                 c.plugins_without_sandbox ? " unless sandbox.plugins_without_sandbox (set: they are ON)"
                                           : " but for the local user");
  }
  return s;
}

JobConfig with_sandbox(JobConfig j, std::shared_ptr<const Sandbox> s) {
  j.sandbox = std::move(s);
  return j;
}

PluginConfig plugin_config(const ServerConfig& c, const Sandbox& s) {
  PluginConfig p;
  p.sandboxed = s.enabled();
  p.allow_without_sandbox = c.plugins_without_sandbox;
  p.admin_dir = c.plugin_dir;
  p.allowed = [q = c.jobs.quotas](const Caller& caller) { return q.limits(caller).plugins; };
  return p;
}

}  // namespace

Shared::Shared(const ServerConfig& c)
    : config(c),
      store(c.data_dir),
      meshes(store),
      sandbox(make_sandbox(c)),
      jobs(std::make_unique<JobScheduler>(meshes, with_sandbox(c.jobs, sandbox))),
      plugins(std::make_unique<PluginService>(store, *jobs, plugin_config(c, *sandbox))),
      courses(std::make_unique<Courses>(store)),
      grading(std::make_unique<Grading>(meshes, *courses, *jobs, *plugins)),
      rooms(std::make_unique<Rooms>(
          store, *courses, [this](const json& e, const Access& readers) { broadcast(e, readers); },
          [this](const std::string& kind, const std::string& id, const Caller& caller) {
            try {
              if (kind == "mesh") {
                const auto rec = store.get_mesh(id, caller);
                return rec && Access{rec->owner}.owned_by(caller);
              }
              return jobs->access(id, caller).owned_by(caller);
            } catch (const std::exception&) {
              return false;
            }
          })),
      router(meshes, {c.static_dir, "0.1.0", jobs.get(), c.gl_platform, std::max(1, c.workers),
                      c.auth_required || !boost::asio::ip::make_address(c.host).is_loopback(), &metrics, plugins.get(),
                      courses.get(), grading.get(), rooms.get()}),
      rate(c.rate_per_s, c.rate_burst),
      ws(meshes,
         {[j = jobs.get()](const std::string& job, const std::string& name, const std::string& format,
                           const Caller& caller) { return j->artifact(job, name, format, caller); },
          [j = jobs.get()](const std::string& job, const Caller& caller) { (void)j->access(job, caller); }},
         router.auth(), &rate, {c.chunk_bytes, c.max_ws_message_bytes}),
      workers(std::size_t(std::max(1, c.workers))),
      tls(tls_context(c)) {
  ws.set_rooms(rooms.get());
  meshes.set_max_upload_bytes(c.max_upload_bytes);  // what a zip upload may unpack to
  if (!c.reader.empty())
    meshes.set_reader({c.reader, c.data_dir / "tmp", c.jobs.memory_mb,
                       std::chrono::milliseconds(std::llround(c.upload_timeout_s * 1000)), sandbox, c.data_dir});
  meshes.set_preview(c.preview);
  rate.on_refused = [m = &metrics] { m->rate_limited(); };
  jobs->set_plugin_resolver([p = plugins.get()](const std::string& id, const std::string& algorithm,
                                                const Caller& caller) { return p->resolve(id, algorithm, caller); });
  jobs->on_event = [r = &router, m = &metrics, p = plugins.get(), g = grading.get()](const json& e,
                                                                                     const Access& readers) {
    m->job_event(e);
    p->on_job_event(e);
    g->on_job_event(e);
    if (r->on_event) r->on_event(e, readers);
  };
}

// The grading thread and the plugins' scanner submit jobs: they stop first.  The scheduler's thread
// sends events through the router and the plugins: it stops before them.
Shared::~Shared() {
  rooms.reset();  // its flusher sends through the sessions, which go before it
  grading->stop();
  plugins->stop();
  jobs.reset();
  grading.reset();
  plugins.reset();
}

void Shared::broadcast(const json& event, const Access& readers) {
  std::vector<std::shared_ptr<EventSink>> live;
  {
    std::lock_guard lock(sessions_mutex_);
    for (auto& [p, w] : sessions_)
      if (auto s = w.lock()) live.push_back(std::move(s));
  }
  for (auto& s : live) s->send_event(event, readers);
}

void Shared::add_session(EventSink* key, std::weak_ptr<EventSink> session) {
  std::lock_guard lock(sessions_mutex_);
  sessions_[key] = std::move(session);
}

void Shared::remove_session(EventSink* key) {
  std::lock_guard lock(sessions_mutex_);
  sessions_.erase(key);
}

bool Shared::admit_connection(const std::string& address, bool loopback, bool* counted) {
  *counted = false;
  const int cap = config.max_connections_per_ip < 0 ? (loopback ? 0 : ServerConfig::kDefaultConnectionsPerIp)
                                                    : config.max_connections_per_ip;
  if (cap <= 0) return true;
  std::lock_guard lock(connections_mutex_);
  int& n = connections_[address];
  if (n < cap) {
    ++n;
    *counted = true;
    return true;
  }
  if (n == 0) connections_.erase(address);
  return false;
}

void Shared::release_connection(const std::string& address) {
  std::lock_guard lock(connections_mutex_);
  if (--connections_[address] <= 0) connections_.erase(address);
}

Peer::Peer(std::shared_ptr<Shared> s, const boost::asio::ip::tcp::socket& socket) : shared(std::move(s)) {
  boost::system::error_code ec;
  const auto ep = socket.remote_endpoint(ec);
  if (!ec) {
    address = ep.address().to_string();
    loopback = ep.address().is_loopback();
  }
  admitted = shared->admit_connection(address, loopback, &counted);
}

Peer::~Peer() {
  if (counted) shared->release_connection(address);
}

std::optional<HttpResponse> over_cap(const Peer& peer) {
  if (peer.admitted) return std::nullopt;
  return error_response(
      503, "too_many_connections",
      "this address has " +
          std::to_string(peer.shared->config.max_connections_per_ip < 0 ? ServerConfig::kDefaultConnectionsPerIp
                                                                        : peer.shared->config.max_connections_per_ip) +
          " connections open, the most allowed; close one and retry");
}

}  // namespace cgview::server
