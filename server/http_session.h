// One HTTP connection, plain or TLS (Beast's advanced_server_flex
// http_session): it reads requests under the server's size and time limits,
// answers each through the Router (heavy routes on the worker pool), and
// hands an upgrade to /api/v1/ws over to a WebSocket session.
#pragma once

#include <boost/beast/core/flat_buffer.hpp>

#include <memory>
#include <optional>

#include "shared_state.h"

namespace cgview::server {

// buffer: bytes already read (TLS detection); refusal: answered to the first
// request instead of serving it (plain HTTP on a TLS port, a client over its
// address's connection cap).
template <class Stream>
void run_http_session(Stream&& stream, boost::beast::flat_buffer buffer, std::shared_ptr<Shared> shared,
                      std::shared_ptr<const Peer> peer, std::optional<HttpResponse> refusal = std::nullopt);

}  // namespace cgview::server
