// The http session's template, compiled once per stream: http_session_plain.cpp
// and http_session_tls.cpp each instantiate it for one, so that the two heavy halves
// (Beast's templates over a TCP and over a TLS stream) build side by side.
// Included by those two files alone.
#pragma once

#include "http_session.h"

#include <utility>  // Boost 1.74's asio/awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket/rfc6455.hpp>

#include <climits>
#include <cstdio>

#include "websocket_session.h"

namespace cgview::server {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace ssl = net::ssl;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

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
  HttpSession(Stream&& stream, beast::flat_buffer buffer, std::shared_ptr<Shared> shared,
              std::shared_ptr<const Peer> peer, std::optional<HttpResponse> refusal = std::nullopt)
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
    stream_.async_read_some(buffer_.prepare(4096),
                            [self = this->shared_from_this()](beast::error_code ec, std::size_t n) {
                              self->disarm();
                              if (ec) return self->expired_ ? self->close() : void();
                              self->buffer_.commit(n);
                              self->read_header();
                            });
  }

  void read_header() {
    request_start_ = Clock::now();
    arm(request_start_ + seconds(config().request_timeout_s));
    http::async_read_header(stream_, buffer_, *parser_,
                            beast::bind_front_handler(&HttpSession::on_header, this->shared_from_this()));
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
    arm(request_start_ +
        seconds(config().request_timeout_s + double(body_bytes_) / std::max(1.0, config().min_body_rate)));
    http::async_read_some(stream_, buffer_, *parser_,
                          [self = this->shared_from_this()](beast::error_code ec, std::size_t n) {
                            if (ec) return self->on_read(ec, n);
                            self->body_bytes_ += n;
                            self->read_body();
                          });
  }

  void on_read(beast::error_code ec, std::size_t) {
    disarm();
    if (ec == http::error::end_of_stream) return close();
    if (ec == http::error::body_limit) {
      return write(
          error_response(413, "payload_too_large",
                         "the body is over the limit of " + std::to_string(config().max_upload_bytes) + " bytes"),
          false);
    }
    if (ec == http::error::header_limit) {
      return write(error_response(431, "headers_too_large",
                                  "the request line and headers are over the limit of " +
                                      std::to_string(config().max_header_bytes) + " bytes"),
                   false);
    }
    if (expired_) {
      char detail[200];
      std::snprintf(detail, sizeof detail,
                    "the request did not arrive in time: headers within %g s, then the body at %g bytes per second",
                    config().request_timeout_s, config().min_body_rate);
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
      if (const auto over = check_rate(shared_->rate, authorization, peer_->address, peer_->loopback)) {
        HttpResponse res = error_response(429, "rate_limited", over->detail);
        res.headers.push_back({"Retry-After", std::to_string(over->retry_after_s)});
        return write(std::move(res), req.keep_alive());
      }
    }
    if (websocket::is_upgrade(req)) {
      if (path != "/api/v1/ws")
        return write(error_response(404, "not_found", "WebSockets are served at /api/v1/ws"), false);
      // A token in the upgrade's header authenticates at once (scripts); a
      // browser, which cannot set it, sends an auth message first.
      if (!authorization.empty() && !shared_->router.auth().authenticate(authorization))
        return write(error_response(401, "unauthorized", "the token is wrong or was revoked"), false);
      lowest().expires_never();
      run_websocket_session(std::move(stream_), parser_->release(), std::move(authorization), shared_, peer_);
      return;
    }
    keep_alive_ = req.keep_alive();
    HttpRequest r{std::string(req.method_string()), std::string(req.target()), std::move(req.body()),
                  std::move(authorization)};
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
      net::post(self->stream_.get_executor(),
                [self, res = std::move(res)]() mutable { self->write(std::move(res), self->keep_alive_); });
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

}  // namespace

template <class Stream>
void run_http_session(Stream&& stream, beast::flat_buffer buffer, std::shared_ptr<Shared> shared,
                      std::shared_ptr<const Peer> peer, std::optional<HttpResponse> refusal) {
  std::make_shared<HttpSession<Stream>>(std::move(stream), std::move(buffer), std::move(shared), std::move(peer),
                                        std::move(refusal))
      ->run();
}

}  // namespace cgview::server
