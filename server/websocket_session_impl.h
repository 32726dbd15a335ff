// The websocket session's template, compiled once per stream: websocket_session_plain.cpp
// and websocket_session_tls.cpp each instantiate it for one, so that the two heavy halves
// (Beast's templates over a TCP and over a TLS stream) build side by side.
// Included by those two files alone.
#pragma once

#include "websocket_session.h"

#include <utility>  // Boost 1.74's asio/awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include <deque>

namespace cgview::server {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using nlohmann::json;

namespace {

template <class Stream>
class WebSocketSession : public EventSink, public std::enable_shared_from_this<WebSocketSession<Stream>> {
 public:
  WebSocketSession(Stream&& stream, std::shared_ptr<Shared> shared, std::shared_ptr<const Peer> peer)
      : ws_(std::move(stream)), shared_(std::move(shared)), peer_(std::move(peer)) {
    shared_->metrics.websocket_opened();
    conn_.address = peer_->address;
    conn_.loopback = peer_->loopback;
  }
  ~WebSocketSession() {
    shared_->ws.closed(conn_);  // a presenter's room ends, a follower leaves
    shared_->metrics.websocket_closed();
    shared_->remove_session(static_cast<EventSink*>(this));
  }

  void run(http::request<http::string_body> req, std::string authorization) {
    conn_.authorization = std::move(authorization);
    conn_.caller = shared_->router.auth().authenticate(conn_.authorization);
    // A silent client is pinged after half the idle time, dropped at its end.
    auto timeout = websocket::stream_base::timeout::suggested(beast::role_type::server);
    timeout.handshake_timeout = seconds(shared_->config.request_timeout_s);
    timeout.idle_timeout = seconds(shared_->config.ws_idle_timeout_s);
    timeout.keep_alive_pings = true;
    ws_.set_option(timeout);
    ws_.read_message_max(shared_->config.max_ws_message_bytes);
    ws_.async_accept(req, beast::bind_front_handler(&WebSocketSession::on_accept, this->shared_from_this()));
  }

  // Thread-safe: sends an event if this session's user may read it.
  void send_event(const json& event, const Access& readers) override {
    net::post(ws_.get_executor(), [self = this->shared_from_this(), event, readers] {
      if (self->shared_->ws.admits_event(self->conn_, readers, self->on_strand())) self->enqueue(WsOut::text(event));
      self->close_if_refused();
    });
  }

 private:
  // Replies made on this session's strand go straight to the queue; those
  // made on a worker are posted to the strand.
  WsEmit on_strand() {
    return [this](WsOut out) { enqueue(std::move(out)); };
  }
  WsEmit from_worker() {
    return [self = this->shared_from_this()](WsOut out) {
      net::post(self->ws_.get_executor(), [self, out = std::move(out)]() mutable { self->enqueue(std::move(out)); });
    };
  }

  void on_accept(beast::error_code ec) {
    if (ec) return;
    shared_->add_session(static_cast<EventSink*>(this), this->weak_from_this());
    // Where a token is needed (off loopback, or --auth required), a
    // connection that never says who it is would hold a descriptor for as
    // long as it answers pings: it has a few seconds.
    if (!conn_.caller) {
      auth_timer_.expires_after(std::chrono::milliseconds(long(shared_->config.ws_auth_timeout_s * 1000)));
      auth_timer_.async_wait([self = this->shared_from_this()](beast::error_code e) {
        if (e || self->conn_.caller || self->closing_) return;
        self->closing_ = true;
        self->ws_.async_close(websocket::close_reason(websocket::close_code::policy_error, "not authenticated in time"),
                              [self](beast::error_code) {});
      });
    }
    do_read();
  }

  void do_read() {
    ws_.async_read(buffer_, beast::bind_front_handler(&WebSocketSession::on_read, this->shared_from_this()));
  }

  void on_read(beast::error_code ec, std::size_t) {
    if (ec == websocket::error::message_too_big)
      return enqueue(shared_->ws.too_big());  // Beast closes the stream after it
    if (ec) {                                 // closed, timed out or broken: the session ends
      auth_timer_.cancel();                   // which holds it: its end is now, not when the timer would fire
      return;
    }
    const std::string text = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    if (auto work = shared_->ws.receive(text, ws_.got_binary(), conn_, on_strand()))
      net::post(shared_->workers, [work = std::move(work), emit = from_worker()] { work(emit); });
    close_if_refused();
    if (!conn_.close) do_read();
  }

  // A refused connection (a wrong or revoked token) closes once its error is written.
  void close_if_refused() {
    if (conn_.close && queue_.empty() && !closing_) close();
  }

  void close() {
    closing_ = true;
    ws_.async_close(websocket::close_code::policy_error, [self = this->shared_from_this()](beast::error_code) {});
  }

  void enqueue(WsOut out) {
    if (closing_) return;
    if (queued_bytes_ + out.size() > shared_->config.max_write_queue_bytes)
      return close();  // a client that does not read
    queued_bytes_ += out.size();
    queue_.push_back(std::move(out));
    if (queue_.size() == 1) do_write();
  }

  void do_write() {
    const WsOut& out = queue_.front();
    ws_.binary(out.binary);
    const std::array<net::const_buffer, 2> buffers{net::buffer(out.head),
                                                   net::buffer(out.body.data(), out.body.size())};
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
    close_if_refused();
  }

  websocket::stream<Stream> ws_;
  beast::flat_buffer buffer_;
  std::shared_ptr<Shared> shared_;
  std::shared_ptr<const Peer> peer_;
  WsConnection conn_;  // on the strand only
  std::deque<WsOut> queue_;
  std::size_t queued_bytes_ = 0;
  bool closing_ = false;
  net::steady_timer auth_timer_{ws_.get_executor()};
};

}  // namespace

template <class Stream>
void run_websocket_session(Stream&& stream, http::request<http::string_body> upgrade, std::string authorization,
                           std::shared_ptr<Shared> shared, std::shared_ptr<const Peer> peer) {
  std::make_shared<WebSocketSession<Stream>>(std::move(stream), std::move(shared), std::move(peer))
      ->run(std::move(upgrade), std::move(authorization));
}

}  // namespace cgview::server
