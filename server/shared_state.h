// What every session of one server shares, as in Beast's chat-multi example:
// the store and its services, the HTTP router and the WebSocket handler, the
// worker pool, the WebSocket sessions that events go to, the rate and
// connection limits, the TLS context.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>

#include <chrono>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <unordered_map>

#include "metrics.h"
#include "mesh_service.h"
#include "plugin_service.h"
#include "rate_limit.h"
#include "router.h"
#include "server.h"
#include "store.h"
#include "teaching/courses.h"
#include "teaching/grading.h"
#include "teaching/rooms.h"
#include "ws_handler.h"

namespace cgview::server {

using PlainStream = boost::beast::tcp_stream;
using TlsStream = boost::beast::ssl_stream<boost::beast::tcp_stream>;

std::chrono::steady_clock::duration seconds(double s);

// A WebSocket session as the event broadcast sees it, over either stream.
struct EventSink {
  virtual ~EventSink() = default;
  virtual void send_event(const nlohmann::json& event, const Access& readers) = 0;
};

struct Shared {
  explicit Shared(const ServerConfig& c);
  ~Shared();
  ServerConfig config;
  Metrics metrics;  // before the router and the scheduler, which report to it
  Store store;
  MeshService meshes;
  std::shared_ptr<const Sandbox> sandbox;  // where workers start (sandbox.h)
  std::unique_ptr<JobScheduler> jobs;
  std::unique_ptr<PluginService> plugins;  // users' algorithms (plugin_service.h)
  std::unique_ptr<Courses> courses;        // classes and their members (teaching/courses.h)
  std::unique_ptr<Grading> grading;        // assignments graded on hidden meshes (teaching/grading.h)
  std::unique_ptr<Rooms> rooms;            // live lectures (teaching/rooms.h)
  Router router;
  RateLimiter rate;
  WsHandler ws;
  boost::asio::thread_pool workers;
  std::optional<boost::asio::ssl::context> tls;  // set: every connection speaks TLS
  // Sends the event to the sessions of the users who may read it.
  void broadcast(const nlohmann::json& event, const Access& readers);
  void add_session(EventSink* key, std::weak_ptr<EventSink> session);
  void remove_session(EventSink* key);
  // A new connection's place under the per-address cap: false when over it.
  // Counts a connection against its address's cap; false when over it.
  // *counted says whether it was counted (release it then).
  bool admit_connection(const std::string& address, bool loopback, bool* counted);
  void release_connection(const std::string& address);

 private:
  std::mutex sessions_mutex_;
  std::unordered_map<EventSink*, std::weak_ptr<EventSink>> sessions_;
  std::mutex connections_mutex_;
  std::unordered_map<std::string, int> connections_;  // open connections per address (with a cap)
};

// A connection's client: its address, and its place under the per-address
// cap (given back when the last session of the connection ends).
struct Peer {
  Peer(std::shared_ptr<Shared> s, const boost::asio::ip::tcp::socket& socket);
  ~Peer();
  std::shared_ptr<Shared> shared;
  std::string address;
  bool loopback = false;
  bool admitted = true;  // false: over max_connections_per_ip, answered 503
  bool counted = false;  // counted against its address's cap
};

// The refusal of a client over its address's connection cap, or nullopt.
std::optional<HttpResponse> over_cap(const Peer& peer);

}  // namespace cgview::server
