// The WebSocket's messages (server/ws_handler.h) over a real store with one
// mesh: any bytes, split at newlines into messages ("$MESH" stands for the
// stored mesh's id, "$TOKEN" for a user's token), each get JSON replies with
// a type (an error with a code and a detail) or binary frames that decode,
// and nothing after a refusal.  No exception may escape the handler.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "auth.h"
#include "frames.h"
#include "fuzz.h"  // fuzz::text
#include "mesh_service.h"
#include "rate_limit.h"
#include "store.h"
#include "ws_handler.h"

namespace {

using namespace cgview;
using nlohmann::json;

struct World {
  World()
      : dir(std::filesystem::temp_directory_path() / ("cgview-fuzz-ws-" + std::to_string(::getpid()))),
        store((std::filesystem::remove_all(dir), dir)),
        meshes(store),
        auth(store, false),
        token(auth.add_user("alice", false)),
        handler(meshes, {}, auth, nullptr, {256, 1 << 20}) {
    // A tetrahedron and a quad: small, so that get_mesh streams several 256-byte frames quickly.
    mesh_id =
        meshes
            .upload("t.off", "",
                    "OFF\n5 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 1 4 2\n")
            .id;
  }
  ~World() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  std::filesystem::path dir;
  server::Store store;
  server::MeshService meshes;
  server::Auth auth;
  std::string token;
  server::WsHandler handler;
  std::string mesh_id;
};

void replace_all(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
}

void check(const server::WsOut& out) {
  if (out.binary) {
    const std::string frame = out.head + std::string(out.body);
    (void)protocol::decode_frame(frame);  // throws InvalidInput for a bad frame: the caller aborts
    return;
  }
  const json j = json::parse(out.head, nullptr, false);
  if (!j.is_object() || !j.contains("type") || !j["type"].is_string()) std::abort();
  if (j["type"] == "error" && (!j.contains("error") || !j["error"].is_string() || !j.contains("detail") ||
                               !j["detail"].is_string() || j["detail"].get<std::string>().empty()))
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static World world;
  server::RateLimiter rate(1, 6);
  const server::WsHandler limited(world.meshes, {}, world.auth, &rate, {256, 1 << 20});
  server::WsConnection conn;
  conn.address = "192.0.2.1";
  conn.caller = world.auth.authenticate("");
  std::string text(fuzz::text(data, size));
  replace_all(text, "$MESH", world.mesh_id);
  replace_all(text, "$TOKEN", world.token);
  const bool binary = !text.empty() && text[0] == '\x01';
  std::size_t start = 0;
  for (int n = 0; start <= text.size() && n < 32; ++n) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view message = std::string_view(text).substr(start, end - start);
    const bool refused = conn.close;
    const auto replies = (n % 2 ? limited : world.handler).handle(message, conn, binary && n == 0);
    if (refused && !replies.empty()) std::abort();  // nothing after a refusal
    try {
      for (const auto& r : replies) check(r);
    } catch (const InvalidInput&) {
      std::abort();  // a frame the server made that its own decoder refuses
    }
    start = end + 1;
  }
  return 0;
}
