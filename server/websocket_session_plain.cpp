#include "websocket_session_impl.h"

namespace cgview::server {

template void run_websocket_session<PlainStream>(PlainStream&&, http::request<http::string_body>, std::string,
                                                 std::shared_ptr<Shared>, std::shared_ptr<const Peer>);

}  // namespace cgview::server
