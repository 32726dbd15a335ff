#include "server.h"

#include <utility>  // Boost 1.74's asio/awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include <climits>
#include <cmath>
#include <deque>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <unordered_map>

#include "core/errors.h"
#include "io/parse_json.h"
#include "metrics.h"
#include "animation_frames.h"
#include "frames.h"
#include "mesh_service.h"
#include "rate_limit.h"
#include "router.h"
#include "store.h"
#include "voxel/voxel_io.h"
#include "voxel_slice.h"

namespace cgview::server {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace ssl = net::ssl;
using tcp = net::ip::tcp;
using nlohmann::json;
using Clock = std::chrono::steady_clock;
using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

namespace {

// A WebSocket session as the event broadcast sees it, over either stream.
struct EventSink {
  virtual ~EventSink() = default;
  virtual void send_event(const json& event, const Access& readers) = 0;
};

std::chrono::steady_clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

// The server's TLS context from the PEM files; throws naming the file at fault.
std::optional<ssl::context> tls_context(const ServerConfig& c) {
  if (c.tls_cert.empty() && c.tls_key.empty()) return std::nullopt;
  if (c.tls_cert.empty() || c.tls_key.empty()) throw std::invalid_argument("TLS needs both a certificate and a key (--tls-cert, --tls-key)");
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
    throw std::runtime_error("TLS: " + c.tls_key.string() + " is not the PEM private key of the certificate (" + e.what() + ")");
  }
  return ctx;
}

struct Peer;

// What every session shares.
struct Shared {
  explicit Shared(const ServerConfig& c)
      : config(c),
        store(c.data_dir),
        meshes(store),
        jobs(std::make_unique<JobScheduler>(meshes, c.jobs)),
        router(meshes, {c.static_dir, "0.1.0", jobs.get(), c.gl_platform, std::max(1, c.workers),
                        c.auth_required || !net::ip::make_address(c.host).is_loopback(), &metrics}),
        workers(std::size_t(std::max(1, c.workers))),
        rate(c.rate_per_s, c.rate_burst),
        tls(tls_context(c)) {
    meshes.set_max_upload_bytes(c.max_upload_bytes);  // what a zip upload may unpack to
    if (!c.reader.empty())
      meshes.set_reader({c.reader, c.data_dir / "tmp", c.jobs.memory_mb,
                         std::chrono::milliseconds(std::llround(c.upload_timeout_s * 1000))});
    meshes.set_preview(c.preview);
    jobs->on_event = [r = &router, m = &metrics](const json& e, const Access& readers) {
      m->job_event(e);
      if (r->on_event) r->on_event(e, readers);
    };
  }
  ~Shared() { jobs.reset(); }  // its thread sends events through the router
  ServerConfig config;
  Metrics metrics;  // before the router and the scheduler, which report to it
  Store store;
  MeshService meshes;
  std::unique_ptr<JobScheduler> jobs;
  Router router;
  net::thread_pool workers;
  std::mutex sessions_mutex;
  std::unordered_map<EventSink*, std::weak_ptr<EventSink>> sessions;
  RateLimiter rate;
  std::optional<ssl::context> tls;  // set: every connection speaks TLS
  std::mutex connections_mutex;
  std::unordered_map<std::string, int> connections;  // open connections per address (with a cap)
  // Sends the event to the sessions of the users who may read it.
  void broadcast(const json& event, const Access& readers);
  // 429's response (or WebSocket error) detail when the request is over the
  // rate limit of its token or address, else nullopt.
  std::optional<std::pair<double, std::string>> over_rate(std::string_view authorization, const Peer& peer);
};

// A connection's client: its address, and its place under the per-address
// cap (given back when the last session of the connection ends).
struct Peer {
  Peer(std::shared_ptr<Shared> s, const tcp::socket& socket) : shared(std::move(s)) {
    beast::error_code ec;
    const auto ep = socket.remote_endpoint(ec);
    if (!ec) {
      address = ep.address().to_string();
      loopback = ep.address().is_loopback();
    }
    const int cap = shared->config.max_connections_per_ip;
    if (cap <= 0) return;
    std::lock_guard lock(shared->connections_mutex);
    int& n = shared->connections[address];
    admitted = n < cap;
    if (admitted) ++n;
    else if (n == 0) shared->connections.erase(address);
  }
  ~Peer() {
    if (shared->config.max_connections_per_ip <= 0 || !admitted) return;
    std::lock_guard lock(shared->connections_mutex);
    if (--shared->connections[address] <= 0) shared->connections.erase(address);
  }
  std::shared_ptr<Shared> shared;
  std::string address;
  bool loopback = false;
  bool admitted = true;  // false: over max_connections_per_ip, answered 503
};

std::optional<std::pair<double, std::string>> Shared::over_rate(std::string_view authorization, const Peer& peer) {
  const std::string key = rate_key(authorization, peer.address, peer.loopback);
  const auto wait = rate.take(key);
  if (!wait) return std::nullopt;
  metrics.rate_limited();
  const double retry = std::max(1.0, std::ceil(*wait));
  return std::pair(retry, "over the rate limit of " + rate.describe() + " for this " +
                              (key.starts_with("token:") ? "token" : "address") + "; retry after " +
                              std::to_string(int(retry)) + " s");
}

// A message queued for a WebSocket: text, or a binary frame header followed
// by a view into a shared payload (the cached Draco bytes are never copied).
struct Outgoing {
  std::string head;
  std::shared_ptr<const void> keep;
  std::string_view body;
  bool binary = false;
  std::size_t size() const { return head.size() + body.size(); }
};

template <class Stream>
class WebSocketSession : public EventSink, public std::enable_shared_from_this<WebSocketSession<Stream>> {
 public:
  WebSocketSession(Stream&& stream, std::shared_ptr<Shared> shared, std::shared_ptr<const Peer> peer)
      : ws_(std::move(stream)), shared_(std::move(shared)), peer_(std::move(peer)) {
    shared_->metrics.websocket_opened();
  }
  ~WebSocketSession() {
    shared_->metrics.websocket_closed();
    std::lock_guard lock(shared_->sessions_mutex);
    shared_->sessions.erase(static_cast<EventSink*>(this));
  }

  // The upgrade request's Authorization header (checked by the caller), or
  // empty: then where a token is required the session waits for an auth message.
  void run(http::request<http::string_body> req, std::string authorization) {
    authorization_ = std::move(authorization);
    caller_ = shared_->router.auth().authenticate(authorization_);
    // A silent client is pinged after half the idle time, dropped at its end.
    auto timeout = websocket::stream_base::timeout::suggested(beast::role_type::server);
    timeout.handshake_timeout = seconds(shared_->config.request_timeout_s);
    timeout.idle_timeout = seconds(shared_->config.ws_idle_timeout_s);
    timeout.keep_alive_pings = true;
    ws_.set_option(timeout);
    ws_.read_message_max(shared_->config.max_ws_message_bytes);
    ws_.async_accept(req, beast::bind_front_handler(&WebSocketSession::on_accept, this->shared_from_this()));
  }

  // Thread-safe: queues a message on this session's strand.
  void send(Outgoing out) {
    net::post(ws_.get_executor(), [self = this->shared_from_this(), out = std::move(out)]() mutable { self->enqueue(std::move(out)); });
  }
  void send_json(const json& j) { send({j.dump(-1, ' ', false, json::error_handler_t::replace), nullptr, {}, false}); }
  // Thread-safe: sends an event if this session's user may read it.
  void send_event(const json& event, const Access& readers) override {
    net::post(ws_.get_executor(), [self = this->shared_from_this(), event, readers] {
      if (self->caller_ && self->still_authorized() && readers.allows(*self->caller_))
        self->enqueue({event.dump(), nullptr, {}, false});
    });
  }

 private:
  void on_accept(beast::error_code ec) {
    if (ec) return;
    {
      std::lock_guard lock(shared_->sessions_mutex);
      shared_->sessions[static_cast<EventSink*>(this)] = this->weak_from_this();
    }
    do_read();
  }

  void do_read() {
    ws_.async_read(buffer_, beast::bind_front_handler(&WebSocketSession::on_read, this->shared_from_this()));
  }

  void on_read(beast::error_code ec, std::size_t) {
    if (ec == websocket::error::message_too_big) {
      send_json({{"type", "error"}, {"request_id", nullptr}, {"error", "payload_too_large"},
                 {"detail", "messages to the server are limited to " + std::to_string(shared_->config.max_ws_message_bytes) + " bytes"}});
      return;  // Beast closes the stream after this error
    }
    if (ec) return;  // closed, timed out or broken: the session ends
    const bool binary = ws_.got_binary();
    const std::string text = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    if (binary) error(nullptr, "bad_request", "binary messages are not accepted; send JSON text");
    else handle(text);
    if (!close_when_sent_) do_read();
  }

  // A missing or wrong token: one error, then the connection closes.
  void refuse(const json& id, const std::string& detail) {
    error(id, "unauthorized", detail);
    close_when_sent_ = true;
  }

  // The token is checked again for every request and event, so that a
  // revoked one stops an open session at once; false (and the session
  // refused) when it was revoked.
  bool still_authorized() {
    if (close_when_sent_) return false;
    if (authorization_.empty()) return true;  // the local user
    if (shared_->router.auth().authenticate(authorization_)) return true;
    refuse(nullptr, "the token was revoked");
    return false;
  }

  void error(const json& request_id, const std::string& code, const std::string& detail) {
    send_json({{"type", "error"}, {"request_id", request_id}, {"error", code}, {"detail", detail}});
  }

  void handle(const std::string& text) {
    json msg;
    try {
      msg = parse_json(text, "the message");
    } catch (const json::exception&) {
      return error(nullptr, "bad_request", "the message is not JSON");
    } catch (const InvalidInput& e) {
      return error(nullptr, "bad_request", e.what());
    }
    if (!msg.is_object()) return error(nullptr, "bad_request", "the message must be a JSON object");
    json id = msg.contains("request_id") ? msg["request_id"] : json(nullptr);
    if (!id.is_null() && !id.is_number_unsigned()) return error(nullptr, "bad_request", "request_id must be a non-negative integer");
    if (!msg.contains("type") || !msg["type"].is_string()) return error(id, "bad_request", "the message has no \"type\"");
    const std::string type = msg["type"];
    if (const auto over = shared_->over_rate(authorization_, *peer_)) {
      return send_json({{"type", "error"}, {"request_id", id}, {"error", "rate_limited"}, {"detail", over->second},
                        {"retry_after_s", over->first}});
    }
    if (type == "auth") {
      const json token = msg.value("token", json());
      authorization_ = token.is_string() && !token.get<std::string>().empty() ? "Bearer " + token.get<std::string>() : "-";
      caller_ = shared_->router.auth().authenticate(authorization_);
      if (!caller_) return refuse(id, "the token is wrong or was revoked");
      return send_json({{"type", "authenticated"}, {"request_id", id}, {"user", caller_->user}, {"admin", caller_->admin}});
    }
    if (!caller_) return refuse(id, "this server needs a token: send {\"type\":\"auth\",\"token\":TOKEN} first");
    if (!still_authorized()) return;
    if (type == "ping") return send_json({{"type", "pong"}, {"request_id", id}});
    if (type == "list_meshes" || type == "get_mesh" || type == "get_slice" || type == "get_animation") {
      net::post(shared_->workers, [self = this->shared_from_this(), msg = std::move(msg), id, type, caller = *caller_] {
        self->work(type, msg, id, caller);
      });
      return;
    }
    error(id, "bad_request", "unknown message type '" + type + "'");
  }

  // On a worker thread.
  void work(const std::string& type, const json& msg, const json& id, const Caller& caller) {
    try {
      if (type == "list_meshes") {
        json list = json::array();
        for (const auto& r : shared_->store.list_meshes(caller)) list.push_back(mesh_json(r));
        return send_json({{"type", "meshes"}, {"request_id", id}, {"meshes", list}});
      }
      if (type == "get_slice") return slice(msg, id, caller);
      if (type == "get_animation") return animation(msg, id, caller);
      if (id.is_null()) return error(id, "bad_request", "get_mesh needs a request_id");
      if (!msg.contains("mesh_id") || !msg["mesh_id"].is_string()) return error(id, "bad_request", "get_mesh needs a \"mesh_id\" string");
      int bits = 14;
      if (msg.contains("quantization")) {
        if (!msg["quantization"].is_number_integer()) return error(id, "bad_request", "quantization must be an integer 1..30");
        bits = msg["quantization"];
      }
      const auto rec = shared_->store.get_mesh(msg["mesh_id"], caller);
      if (!rec) return error(id, "not_found", "no mesh with id '" + msg["mesh_id"].get<std::string>() + "'");
      // lod: "full" (the default, one reply), "preview" (the preview of a big
      // mesh, else the mesh) or "progressive" (the preview of a big mesh,
      // then the mesh: two replies).  API.md, "Big meshes".
      const json lod_value = msg.value("lod", json("full"));
      const std::string lod = lod_value.is_string() ? lod_value.get<std::string>() : lod_value.dump();
      if (lod != "full" && lod != "preview" && lod != "progressive")
        return error(id, "bad_request", "lod must be \"full\", \"preview\" or \"progressive\", got " + lod_value.dump());
      check_quantization_bits(bits);  // before a preview is streamed
      const bool preview = lod != "full" && shared_->meshes.has_preview(*rec);
      if (preview) stream(*rec, shared_->meshes.preview(*rec), "preview", id);
      if (!preview || lod == "progressive") stream(*rec, shared_->meshes.draco(*rec, bits), "full", id);
    } catch (const InvalidInput& e) {
      error(id, "bad_request", e.what());
    } catch (const std::exception& e) {
      error(id, "internal", e.what());
    }
  }

  // mesh_begin, the Draco bytes in chunks, mesh_end; level "preview" or "full".
  void stream(const MeshRecord& rec, const std::shared_ptr<const EncodedMesh>& enc, const char* level, const json& id) {
    const std::uint32_t rid = std::uint32_t(id.get<std::uint64_t>());
    const std::size_t chunk = shared_->config.chunk_bytes;
    const std::size_t total = enc->bytes.size();
    const std::size_t count = total == 0 ? 1 : (total + chunk - 1) / chunk;
    send_json({{"type", "mesh_begin"}, {"request_id", id}, {"mesh_id", rec.id}, {"encoding", "draco"}, {"level", level},
               {"bytes", total}, {"chunks", count}, {"vertices", enc->vertices}, {"faces", enc->faces},
               {"has_normals", enc->has_normals}, {"has_colors", enc->has_colors}});
    for (std::size_t i = 0; i < count; ++i) {
      const std::string_view part = std::string_view(enc->bytes).substr(i * chunk, chunk);
      send({protocol::encode_frame_header({protocol::FrameKind::draco_mesh, rid, std::uint32_t(i), std::uint32_t(count), total}),
            enc, part, true});
    }
    send_json({{"type", "mesh_end"}, {"request_id", id}});
  }

  // get_animation: a job's animation artifact (chaos_animate's frames) as
  // quantized deltas, zlib-compressed, in frames of kind 3
  // (protocol/animation_frames.h, API.md).  On a worker thread.
  void animation(const json& msg, const json& id, const Caller& caller) {
    if (id.is_null()) return error(id, "bad_request", "get_animation needs a request_id");
    if (!msg.contains("job_id") || !msg["job_id"].is_string()) return error(id, "bad_request", "get_animation needs a \"job_id\" string");
    const std::string artifact = msg.contains("artifact") && msg["artifact"].is_string() ? msg["artifact"].get<std::string>() : "frames";
    std::string raw;
    try {
      raw = shared_->jobs->artifact(msg["job_id"], artifact, "frames", caller).bytes;
    } catch (const std::out_of_range& e) {
      return error(id, "not_found", e.what());
    } catch (const UnsupportedFormat&) {
      return error(id, "bad_request", "artifact '" + artifact + "' of job " + msg["job_id"].get<std::string>() + " is not an animation");
    }
    auto payload = std::make_shared<const std::string>(protocol::encode_animation_payload(raw));
    const std::uint32_t rid = std::uint32_t(id.get<std::uint64_t>());
    const std::size_t chunk = shared_->config.chunk_bytes;
    const std::size_t total = payload->size();
    const std::size_t count = (total + chunk - 1) / chunk;
    send_json({{"type", "animation_begin"}, {"request_id", id}, {"job_id", msg["job_id"]}, {"artifact", artifact},
               {"encoding", "frames-delta-zlib"}, {"raw_bytes", raw.size()}, {"bytes", total}, {"chunks", count}});
    for (std::size_t i = 0; i < count; ++i) {
      const std::string_view part = std::string_view(*payload).substr(i * chunk, chunk);
      send({protocol::encode_frame_header({protocol::FrameKind::animation, rid, std::uint32_t(i), std::uint32_t(count), total}),
            payload, part, true});
    }
    send_json({{"type", "animation_end"}, {"request_id", id}});
  }

  // get_slice: a 2D slice of a job's voxel grid artifact, zlib-compressed
  // in voxel-slice frames (protocol/voxel_slice.h, API.md).  On a worker thread.
  void slice(const json& msg, const json& id, const Caller& caller) {
    if (id.is_null()) return error(id, "bad_request", "get_slice needs a request_id");
    if (!msg.contains("job_id") || !msg["job_id"].is_string()) return error(id, "bad_request", "get_slice needs a \"job_id\" string");
    const std::string artifact = msg.contains("artifact") && msg["artifact"].is_string() ? msg["artifact"].get<std::string>() : "grid";
    int axis = -1;
    if (msg.contains("axis") && msg["axis"].is_string()) {
      const std::string a = msg["axis"];
      axis = a == "x" ? 0 : a == "y" ? 1 : a == "z" ? 2 : -1;
    } else if (msg.contains("axis") && msg["axis"].is_number_integer()) {
      axis = msg["axis"].get<int>();
    }
    if (axis < 0 || axis > 2) return error(id, "bad_request", "get_slice needs an \"axis\": \"x\", \"y\" or \"z\" (or 0, 1, 2)");
    if (!msg.contains("index") || !msg["index"].is_number_integer())
      return error(id, "bad_request", "get_slice needs an integer \"index\"");
    const long long index = msg["index"].get<long long>();
    VoxelGrid grid;
    try {
      const ArtifactBytes a = shared_->jobs->artifact(msg["job_id"], artifact, "nrrd", caller);
      grid = decode_nrrd(a.bytes, artifact);
    } catch (const std::out_of_range& e) {
      return error(id, "not_found", e.what());
    } catch (const UnsupportedFormat&) {
      return error(id, "bad_request", "artifact '" + artifact + "' of job " + msg["job_id"].get<std::string>() + " is not a voxel grid");
    }
    if (index < INT_MIN || index > INT_MAX) return error(id, "bad_request", "slice index " + std::to_string(index) + " is out of range");
    const VoxelSlice sl = cgview::slice(grid, axis, int(index));  // InvalidInput out of range: bad_request
    auto payload = std::make_shared<const std::string>(protocol::encode_slice_payload(grid, sl));
    const std::uint32_t rid = std::uint32_t(id.get<std::uint64_t>());
    const std::size_t chunk = shared_->config.chunk_bytes;
    const std::size_t total = payload->size();
    const std::size_t count = (total + chunk - 1) / chunk;
    const auto d = grid.dims();
    send_json({{"type", "slice"}, {"request_id", id}, {"job_id", msg["job_id"]}, {"artifact", artifact}, {"axis", std::string(1, "xyz"[axis])},
               {"index", index}, {"width", sl.width}, {"height", sl.height}, {"dims", {d[0], d[1], d[2]}},
               {"voxel_size", grid.voxel_size()}, {"origin", {grid.origin().x, grid.origin().y, grid.origin().z}},
               {"encoding", "zlib"}, {"bytes", total}, {"chunks", count}});
    for (std::size_t i = 0; i < count; ++i) {
      const std::string_view part = std::string_view(*payload).substr(i * chunk, chunk);
      send({protocol::encode_frame_header({protocol::FrameKind::voxel_slice, rid, std::uint32_t(i), std::uint32_t(count), total}),
            payload, part, true});
    }
    send_json({{"type", "slice_end"}, {"request_id", id}});
  }

  void enqueue(Outgoing out) {
    if (closing_) return;
    if (queued_bytes_ + out.size() > shared_->config.max_write_queue_bytes) {
      // A client that does not read is dropped rather than left to grow memory.
      closing_ = true;
      ws_.async_close(websocket::close_code::policy_error, [self = this->shared_from_this()](beast::error_code) {});
      return;
    }
    queued_bytes_ += out.size();
    queue_.push_back(std::move(out));
    if (queue_.size() == 1) do_write();
  }

  void do_write() {
    const Outgoing& out = queue_.front();
    ws_.binary(out.binary);
    const std::array<net::const_buffer, 2> buffers{net::buffer(out.head), net::buffer(out.body.data(), out.body.size())};
    ws_.async_write(buffers, beast::bind_front_handler(&WebSocketSession::on_write, this->shared_from_this()));
  }

  void on_write(beast::error_code ec, std::size_t) {
    if (ec) {
      queue_.clear();
      queued_bytes_ = 0;
      return;
    }
    queued_bytes_ -= queue_.front().size();
    queue_.pop_front();
    if (!queue_.empty()) return do_write();
    if (close_when_sent_ && !closing_) {
      closing_ = true;
      ws_.async_close(websocket::close_code::policy_error, [self = this->shared_from_this()](beast::error_code) {});
    }
  }

  websocket::stream<Stream> ws_;
  beast::flat_buffer buffer_;
  std::shared_ptr<Shared> shared_;
  std::shared_ptr<const Peer> peer_;
  std::deque<Outgoing> queue_;
  std::size_t queued_bytes_ = 0;
  bool closing_ = false;
  bool close_when_sent_ = false;  // refused: close once the error is written
  std::optional<Caller> caller_;  // set once authenticated; read on the strand only
  std::string authorization_;     // "Bearer TOKEN", checked again for each request; empty: the local user
};

void Shared::broadcast(const json& event, const Access& readers) {
  std::vector<std::shared_ptr<EventSink>> live;
  {
    std::lock_guard lock(sessions_mutex);
    for (auto& [p, w] : sessions)
      if (auto s = w.lock()) live.push_back(std::move(s));
  }
  for (auto& s : live) s->send_event(event, readers);
}

// One HTTP connection, plain or TLS.  Reading is bounded by one deadline
// timer of its own (Beast's stream timer closes the socket, which would leave
// no way to answer 408): no request begun within idle_timeout_s closes the
// connection; a request's headers must arrive within request_timeout_s of its
// first byte, its body at min_body_rate on average after that.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
 public:
  static constexpr bool tls = std::is_same_v<Stream, TlsStream>;

  // buffer: bytes already read (TLS detection); refusal: answered to the
  // first request instead of serving it (plain HTTP on a TLS port, a client
  // over its address's connection cap).
  HttpSession(Stream&& stream, beast::flat_buffer buffer, std::shared_ptr<Shared> shared, std::shared_ptr<const Peer> peer,
              std::optional<HttpResponse> refusal = std::nullopt)
      : stream_(std::move(stream)),
        buffer_(std::move(buffer)),
        shared_(std::move(shared)),
        peer_(std::move(peer)),
        refusal_(std::move(refusal)),
        timer_(stream_.get_executor()) {}

  void run() {
    net::dispatch(stream_.get_executor(), [self = this->shared_from_this()] {
      if constexpr (tls) {
        self->arm(Clock::now() + seconds(self->shared_->config.request_timeout_s));
        self->stream_.async_handshake(ssl::stream_base::server, self->buffer_.data(),
                                      [self](beast::error_code ec, std::size_t used) {
                                        self->disarm();
                                        if (ec) return;
                                        self->buffer_.consume(used);
                                        self->do_read();
                                      });
      } else {
        self->do_read();
      }
    });
  }

 private:
  const ServerConfig& config() const { return shared_->config; }
  beast::tcp_stream& lowest() { return beast::get_lowest_layer(stream_); }

  // Cancels the pending read at `at` (the handler sees operation_aborted
  // with expired_ set).
  void arm(Clock::time_point at) {
    timer_.expires_at(at);
    timer_.async_wait([self = this->shared_from_this(), gen = ++timer_gen_](beast::error_code ec) {
      if (ec || gen != self->timer_gen_) return;
      self->expired_ = true;
      beast::error_code ignored;
      self->lowest().socket().cancel(ignored);
    });
  }
  void disarm() {
    ++timer_gen_;
    timer_.cancel();
  }

  void do_read() {
    parser_.emplace();
    parser_->body_limit(config().max_upload_bytes);
    parser_->header_limit(std::uint32_t(std::min<std::size_t>(config().max_header_bytes, UINT32_MAX)));
    lowest().expires_never();
    if (buffer_.size() > 0) return read_header();
    // Between requests: wait for a first byte, at most idle_timeout_s.
    arm(Clock::now() + seconds(config().idle_timeout_s));
    stream_.async_read_some(buffer_.prepare(4096), [self = this->shared_from_this()](beast::error_code ec, std::size_t n) {
      self->disarm();
      if (ec) return self->expired_ ? self->close() : void();
      self->buffer_.commit(n);
      self->read_header();
    });
  }

  void read_header() {
    request_start_ = Clock::now();
    arm(request_start_ + seconds(config().request_timeout_s));
    http::async_read_header(stream_, buffer_, *parser_, beast::bind_front_handler(&HttpSession::on_header, this->shared_from_this()));
  }

  // The header alone: refuse a body that is announced too large before it
  // is sent, and answer "Expect: 100-continue" (curl sends it for uploads).
  void on_header(beast::error_code ec, std::size_t n) {
    if (ec) return on_read(ec, n);
    const auto& req = parser_->get();
    if (parser_->content_length() && *parser_->content_length() > config().max_upload_bytes)
      return on_read(http::error::body_limit, n);
    body_bytes_ = 0;
    if (!refusal_ && beast::iequals(req[http::field::expect], "100-continue")) {
      auto cont = std::make_shared<http::response<http::empty_body>>(http::status::continue_, 11);
      http::async_write(stream_, *cont, [self = this->shared_from_this(), cont](beast::error_code ec, std::size_t) {
        if (ec) return self->disarm();
        self->read_body();
      });
      return;
    }
    read_body();
  }

  // The body a piece at a time, each piece due by when the client would
  // fall under min_body_rate since the request began (plus its grace).
  void read_body() {
    if (parser_->is_done()) return on_read({}, 0);
    arm(request_start_ + seconds(config().request_timeout_s + double(body_bytes_) / std::max(1.0, config().min_body_rate)));
    http::async_read_some(stream_, buffer_, *parser_, [self = this->shared_from_this()](beast::error_code ec, std::size_t n) {
      if (ec) return self->on_read(ec, n);
      self->body_bytes_ += n;
      self->read_body();
    });
  }

  void on_read(beast::error_code ec, std::size_t) {
    disarm();
    if (ec == http::error::end_of_stream) return close();
    if (ec == http::error::body_limit) {
      return write(error_response(413, "payload_too_large",
                                  "the body is over the limit of " + std::to_string(config().max_upload_bytes) + " bytes"),
                   false);
    }
    if (ec == http::error::header_limit) {
      return write(error_response(431, "headers_too_large",
                                  "the request line and headers are over the limit of " + std::to_string(config().max_header_bytes) +
                                      " bytes"),
                   false);
    }
    if (expired_) {
      char detail[200];
      std::snprintf(detail, sizeof detail,
                    "the request did not arrive in time: headers within %g s, then the body at %g bytes per second", config().request_timeout_s,
                    config().min_body_rate);
      return write(error_response(408, "request_timeout", detail), false);
    }
    if (ec == beast::error::timeout || ec == net::error::operation_aborted || ec == net::error::connection_reset ||
        ec == net::error::eof || ec == ssl::error::stream_truncated)
      return;
    if (ec) return write(error_response(400, "bad_request", "malformed HTTP request: " + ec.message()), false);
    if (refusal_) return write(std::move(*refusal_), false);

    http::request<http::string_body>& req = parser_->get();
    std::string authorization(req[http::field::authorization]);
    const std::string path = split_target(std::string(req.target())).first;
    if (path.starts_with("/api/")) {
      if (const auto over = shared_->over_rate(authorization, *peer_)) {
        HttpResponse res = error_response(429, "rate_limited", over->second);
        res.headers.push_back({"Retry-After", std::to_string(int(over->first))});
        return write(std::move(res), req.keep_alive());
      }
    }
    if (websocket::is_upgrade(req)) {
      if (path != "/api/v1/ws") return write(error_response(404, "not_found", "WebSockets are served at /api/v1/ws"), false);
      // A token in the upgrade's header authenticates at once (scripts); a
      // browser, which cannot set it, sends an auth message first.
      if (!authorization.empty() && !shared_->router.auth().authenticate(authorization))
        return write(error_response(401, "unauthorized", "the token is wrong or was revoked"), false);
      lowest().expires_never();
      std::make_shared<WebSocketSession<Stream>>(std::move(stream_), shared_, peer_)->run(parser_->release(), std::move(authorization));
      return;
    }
    keep_alive_ = req.keep_alive();
    HttpRequest r{std::string(req.method_string()), std::string(req.target()), std::move(req.body()), std::move(authorization)};
    const bool head = r.method == "HEAD";
    if (head) r.method = "GET";
    if (!shared_->router.is_heavy(r)) {
      HttpResponse res = shared_->router.handle(r);
      if (head) res.body.clear();
      return write(std::move(res), keep_alive_);
    }
    // Heavy routes run on a worker; the response comes back on this strand.
    net::post(shared_->workers, [self = this->shared_from_this(), r = std::move(r), head]() mutable {
      HttpResponse res = self->shared_->router.handle(r);
      if (head) res.body.clear();
      net::post(self->stream_.get_executor(), [self, res = std::move(res)]() mutable { self->write(std::move(res), self->keep_alive_); });
    });
  }

  void write(HttpResponse r, bool keep_alive) {
    auto res = std::make_shared<http::response<http::string_body>>(http::status(r.status), 11);
    res->set(http::field::server, "cgview");
    if (!r.content_type.empty()) res->set(http::field::content_type, r.content_type);
    for (const auto& [k, v] : r.headers) res->set(k, v);
    res->body() = std::move(r.body);
    res->keep_alive(keep_alive);
    res->prepare_payload();
    lowest().expires_after(seconds(config().write_timeout_s));
    http::async_write(stream_, *res, [self = this->shared_from_this(), res](beast::error_code ec, std::size_t) {
      if (ec) return;
      if (!res->keep_alive()) return self->close();
      self->do_read();
    });
  }

  void close() {
    beast::error_code ec;
    if constexpr (tls) {
      lowest().expires_after(std::chrono::seconds(5));
      stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {});
    } else {
      stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
    }
  }

  Stream stream_;
  beast::flat_buffer buffer_;
  std::shared_ptr<Shared> shared_;
  std::shared_ptr<const Peer> peer_;
  std::optional<HttpResponse> refusal_;
  net::steady_timer timer_;
  unsigned timer_gen_ = 0;
  bool expired_ = false;
  Clock::time_point request_start_;
  std::size_t body_bytes_ = 0;
  std::optional<http::request_parser<http::string_body>> parser_;
  bool keep_alive_ = true;
};

// The refusal of a client over its address's connection cap, or nullopt.
std::optional<HttpResponse> over_cap(const Peer& peer) {
  if (peer.admitted) return std::nullopt;
  return error_response(503, "too_many_connections",
                        "this address has " + std::to_string(peer.shared->config.max_connections_per_ip) +
                            " connections open, the most allowed; close one and retry");
}

// On a TLS server: the first bytes say whether the client speaks TLS; one
// that speaks plain HTTP gets one 400 saying so (Beast's advanced_server_flex).
class Detector : public std::enable_shared_from_this<Detector> {
 public:
  Detector(tcp::socket&& socket, std::shared_ptr<Shared> shared, std::shared_ptr<const Peer> peer)
      : stream_(std::move(socket)), shared_(std::move(shared)), peer_(std::move(peer)) {}
  void run() {
    net::dispatch(stream_.get_executor(), [self = shared_from_this()] {
      self->stream_.expires_after(seconds(self->shared_->config.request_timeout_s));
      beast::async_detect_ssl(self->stream_, self->buffer_, beast::bind_front_handler(&Detector::on_detect, self));
    });
  }

 private:
  void on_detect(beast::error_code ec, bool tls) {
    if (ec) return;
    stream_.expires_never();
    if (tls) {
      std::make_shared<HttpSession<TlsStream>>(TlsStream(std::move(stream_), *shared_->tls), std::move(buffer_), shared_, peer_,
                                               over_cap(*peer_))
          ->run();
    } else {
      std::make_shared<HttpSession<PlainStream>>(
          std::move(stream_), std::move(buffer_), shared_, peer_,
          error_response(400, "tls_required", "this server speaks TLS only: use https:// (and wss:// for the WebSocket)"))
          ->run();
    }
  }
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::shared_ptr<Shared> shared_;
  std::shared_ptr<const Peer> peer_;
};

}  // namespace

struct Server::Impl {
  explicit Impl(const ServerConfig& c) : shared(std::make_shared<Shared>(c)), acceptor(ioc) {
    shared->router.on_event = [s = shared.get()](const json& e, const Access& readers) { s->broadcast(e, readers); };
    const tcp::endpoint ep(net::ip::make_address(c.host), c.port);
    acceptor.open(ep.protocol());
    acceptor.set_option(net::socket_base::reuse_address(true));
    acceptor.bind(ep);
    acceptor.listen(net::socket_base::max_listen_connections);
    // Where a job's worker on another machine calls back, unless the config
    // says: this address, or this machine's name where it listens on all.
    const auto address = ep.address();
    std::string host = c.host;
    if (address.is_unspecified()) {
      char name[256] = {};
      host = ::gethostname(name, sizeof name - 1) == 0 && name[0] ? name : "127.0.0.1";
    } else if (address.is_v6()) {
      host = "[" + c.host + "]";
    }
    shared->jobs->set_server_url(std::string(shared->tls ? "https" : "http") + "://" + host + ":" +
                                 std::to_string(acceptor.local_endpoint().port()));
    shared->jobs->start();
  }
  void accept() {
    acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket socket) {
      if (!ec) {
        // Small messages (JSON replies, a stream's last chunk) go out at
        // once instead of waiting up to 40 ms for the client's delayed ACK.
        beast::error_code ignored;
        socket.set_option(tcp::no_delay(true), ignored);
        auto peer = std::make_shared<const Peer>(shared, socket);
        if (shared->tls)
          std::make_shared<Detector>(std::move(socket), shared, peer)->run();
        else
          std::make_shared<HttpSession<PlainStream>>(PlainStream(std::move(socket)), beast::flat_buffer(), shared, peer, over_cap(*peer))
              ->run();
      }
      if (acceptor.is_open()) accept();
    });
  }
  net::io_context ioc{1};
  std::shared_ptr<Shared> shared;
  tcp::acceptor acceptor;
};

Server::Server(const ServerConfig& config) : impl_(std::make_unique<Impl>(config)) {}
Server::~Server() {
  stop();
  impl_->shared->workers.join();
}
unsigned short Server::port() const { return impl_->acceptor.local_endpoint().port(); }
bool Server::tls() const { return impl_->shared->tls.has_value(); }
MeshService& Server::meshes() { return impl_->shared->meshes; }
JobScheduler& Server::jobs() { return *impl_->shared->jobs; }

void Server::run() {
  net::signal_set signals(impl_->ioc, SIGINT, SIGTERM);
  signals.async_wait([this](beast::error_code, int) { stop(); });
  impl_->accept();
  impl_->ioc.run();
}

void Server::stop() {
  net::post(impl_->ioc, [this] {
    beast::error_code ec;
    impl_->acceptor.close(ec);
    impl_->ioc.stop();
  });
}

}  // namespace cgview::server
