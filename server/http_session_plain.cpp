#include "http_session_impl.h"

namespace cgview::server {

template void run_http_session<PlainStream>(PlainStream&&, beast::flat_buffer, std::shared_ptr<Shared>,
                                            std::shared_ptr<const Peer>, std::optional<HttpResponse>);

}  // namespace cgview::server
