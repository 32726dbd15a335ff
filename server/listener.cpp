// The listener (Beast's advanced_server_flex listener and detect_session):
// it accepts connections, counts them per address, and on a TLS server lets
// the first bytes say whether the client speaks TLS.  Server's public face.
#include "server.h"

#include <chrono>
#include <cstdio>
#include <utility>  // Boost 1.74's asio/awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>

#include <unistd.h>

#include "http_session.h"
#include "jobs/scheduler.h"
#include "shared_state.h"

namespace cgview::server {

namespace net = boost::asio;
namespace beast = boost::beast;
using tcp = net::ip::tcp;
using nlohmann::json;

namespace {

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
      run_http_session(TlsStream(std::move(stream_), *shared_->tls), std::move(buffer_), shared_, peer_,
                       over_cap(*peer_));
    } else {
      run_http_session(PlainStream(std::move(stream_)), std::move(buffer_), shared_, peer_,
                       error_response(400, "tls_required",
                                      "this server speaks TLS only: use https:// (and wss:// for the WebSocket)"));
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
      if (ec == net::error::no_descriptors || ec == std::errc::too_many_files_open_in_system) {
        // Out of file descriptors: the connection waits in the backlog, so
        // accepting again at once would spin on the same error.  Wait for a
        // connection to close, and say so once an episode.
        if (!out_of_descriptors)
          std::fprintf(stderr, "cgview-server: out of file descriptors (%s): new connections wait\n",
                       ec.message().c_str());
        out_of_descriptors = true;
        backoff.expires_after(std::chrono::milliseconds(50));
        backoff.async_wait([this](beast::error_code) {
          if (acceptor.is_open()) accept();
        });
        return;
      }
      if (!ec) {
        out_of_descriptors = false;
        // Small messages (JSON replies, a stream's last chunk) go out at
        // once instead of waiting up to 40 ms for the client's delayed ACK.
        beast::error_code ignored;
        socket.set_option(tcp::no_delay(true), ignored);
        auto peer = std::make_shared<const Peer>(shared, socket);
        if (shared->tls) std::make_shared<Detector>(std::move(socket), shared, peer)->run();
        else run_http_session(PlainStream(std::move(socket)), beast::flat_buffer(), shared, peer, over_cap(*peer));
      }
      if (acceptor.is_open()) accept();
    });
  }
  net::io_context ioc{1};
  std::shared_ptr<Shared> shared;
  tcp::acceptor acceptor;
  net::steady_timer backoff{ioc};
  bool out_of_descriptors = false;
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
