// One WebSocket connection (Beast's chat-multi websocket_session): it reads
// messages, hands each to the WsHandler (light work on its strand, the rest
// on the worker pool), writes the replies and the events its user may read
// in order, and drops a client whose queue outgrows the limit.
#pragma once

#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>

#include <memory>
#include <string>

#include "shared_state.h"

namespace cgview::server {

// Starts the session on an upgrade request already read (plain or TLS
// stream).  authorization: the request's Authorization header, already
// checked; empty: where a token is required the client sends an auth message.
template <class Stream>
void run_websocket_session(Stream&& stream, boost::beast::http::request<boost::beast::http::string_body> upgrade,
                           std::string authorization, std::shared_ptr<Shared> shared, std::shared_ptr<const Peer> peer);

}  // namespace cgview::server
