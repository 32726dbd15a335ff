// The WebSocket's messages through the handler alone (no sockets): errors,
// the token's life, the rate limit, who gets which event, and a mesh
// streamed in frames that reassemble to what the store's Draco reads back as.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "frames.h"
#include "io/mesh_io.h"
#include "store.h"
#include "voxel/voxel_io.h"
#include "voxel_slice.h"
#include "rate_limit.h"
#include "router_harness.h"
#include "test_support.h"
#include "ws_handler.h"

namespace cgview::server {
namespace {

using nlohmann::json;

json parse(const WsOut& out) {
  EXPECT_FALSE(out.binary);
  return json::parse(out.head, nullptr, false);
}

// One reply, an error with this code (and a detail); returns it.
json expect_one_error(const std::vector<WsOut>& replies, const std::string& code) {
  EXPECT_EQ(replies.size(), 1u);
  if (replies.empty()) return json::object();
  const json j = parse(replies[0]);
  EXPECT_EQ(j.value("type", ""), "error") << j;
  EXPECT_EQ(j.value("error", ""), code) << j;
  EXPECT_FALSE(j.value("detail", "").empty()) << j;
  return j;
}

class WsHandlerTest : public test::RouterFixture {
 protected:
  void open_local() {
    make_dir("ws-");
    open(dir_ / "data", std::nullopt, RouterConfig{});
  }
  WsHandler handler(RateLimiter* rate = nullptr, std::size_t chunk = 64) const {
    return WsHandler(*meshes_, {}, router_->auth(), rate, {chunk, 1024});
  }
  // A connection as the session opens it: the upgrade's Authorization header.
  WsConnection connect(const std::string& authorization = "", const std::string& address = "127.0.0.1") const {
    WsConnection c;
    c.address = address;
    c.loopback = address == "127.0.0.1";
    c.authorization = authorization;
    c.caller = router_->auth().authenticate(authorization);
    return c;
  }
};

TEST_F(WsHandlerTest, EachBadMessageGetsOneErrorAndTheConnectionStaysOpen) {
  open_local();
  const WsHandler ws = handler();
  WsConnection conn = connect();
  struct Case {
    std::string text, code, detail_part;
  };
  for (const Case& c : std::vector<Case>{
           {"not json", "bad_request", "not JSON"},
           {"[1,2]", "bad_request", "JSON object"},
           {R"({"type":"ping","request_id":-1})", "bad_request", "request_id"},
           {R"({"request_id":1})", "bad_request", "\"type\""},
           {R"({"type":"teleport","request_id":1})", "bad_request", "teleport"},
           {R"({"type":"get_mesh"})", "bad_request", "request_id"},
           {R"({"type":"get_mesh","request_id":2})", "bad_request", "mesh_id"},
           {R"({"type":"get_mesh","request_id":3,"mesh_id":"nope"})", "not_found", "nope"},
           {R"({"type":"get_slice","request_id":4,"job_id":"j","axis":"w","index":0})", "bad_request", "axis"},
           {R"({"type":"get_slice","request_id":5,"job_id":"j","axis":"x","index":0})", "not_found", "no jobs"},
           {R"({"type":"get_animation","request_id":6})", "bad_request", "job_id"},
       }) {
    SCOPED_TRACE(c.text);
    const json e = expect_one_error(ws.handle(c.text, conn), c.code);
    EXPECT_NE(e.value("detail", "").find(c.detail_part), std::string::npos) << e;
    EXPECT_FALSE(conn.close);
  }
  expect_one_error(ws.handle("{}", conn, /*binary=*/true), "bad_request");
  const json big = parse(ws.too_big());
  EXPECT_EQ(big["error"], "payload_too_large");
  EXPECT_NE(big["detail"].get<std::string>().find("1024 bytes"), std::string::npos);
  const auto pong = ws.handle(R"({"type":"ping","request_id":9})", conn);
  ASSERT_EQ(pong.size(), 1u);
  EXPECT_EQ(parse(pong[0]), json({{"type", "pong"}, {"request_id", 9}}));
}

TEST_F(WsHandlerTest, GetMeshStreamsTheStoredMeshInFramesThatReassemble) {
  open_local();
  const std::string file = test::read_bytes(test::sample("bunny00.off"));
  const MeshRecord rec = meshes_->upload("bunny00.off", "", file);
  const Mesh reference = read_mesh(test::sample("bunny00.off"));
  const WsHandler ws = handler(nullptr, 1000);
  WsConnection conn = connect();
  const auto replies = ws.handle(R"({"type":"get_mesh","request_id":7,"mesh_id":")" + rec.id + R"("})", conn);
  ASSERT_GE(replies.size(), 3u);
  const json begin = parse(replies.front());
  EXPECT_EQ(begin["type"], "mesh_begin");
  EXPECT_EQ(begin["request_id"], 7);
  EXPECT_EQ(begin["level"], "full");
  EXPECT_EQ(begin["vertices"], reference.num_vertices());
  EXPECT_EQ(begin["faces"], reference.num_faces());
  const std::size_t chunks = begin["chunks"];
  ASSERT_EQ(replies.size(), chunks + 2);
  EXPECT_GT(chunks, 1u) << "the mesh should need several 1000-byte chunks";
  std::string payload;
  for (std::size_t i = 0; i < chunks; ++i) {
    const WsOut& f = replies[1 + i];
    ASSERT_TRUE(f.binary);
    EXPECT_LE(f.body.size(), 1000u);
    std::string_view chunk;
    const std::string frame = f.head + std::string(f.body);
    const protocol::FrameHeader h = protocol::decode_frame(frame, &chunk);
    EXPECT_EQ(h.kind, protocol::FrameKind::draco_mesh);
    EXPECT_EQ(h.request_id, 7u);
    EXPECT_EQ(h.chunk_index, i);
    EXPECT_EQ(h.chunk_count, chunks);
    EXPECT_EQ(h.total_bytes, begin["bytes"].get<std::uint64_t>());
    payload += chunk;
  }
  EXPECT_EQ(parse(replies.back()), json({{"type", "mesh_end"}, {"request_id", 7}}));
  // The reassembled payload is a Draco file of the uploaded mesh.
  const Mesh decoded = read_mesh_bytes(payload, MeshFormat::drc, "bunny00.drc").mesh;
  EXPECT_EQ(decoded.num_vertices(), reference.num_vertices());
  EXPECT_EQ(decoded.num_faces(), reference.num_faces());
}

TEST_F(WsHandlerTest, ATokenIsNeededChecksEachMessageAndARevokedOneClosesTheConnection) {
  make_dir("ws-");
  open_with_users(dir_ / "data", JobConfig{});
  const WsHandler ws = handler();
  const MeshRecord alices = meshes_->upload("cube.off", "", test::read_bytes(test::sample("cube.off")), "alice");
  const MeshRecord bobs = meshes_->upload("tetra.off", "", test::read_bytes(test::sample("tetrahedron.off")), "bob");

  WsConnection anonymous = connect();
  EXPECT_FALSE(anonymous.caller);
  expect_one_error(ws.handle(R"({"type":"ping","request_id":1})", anonymous), "unauthorized");
  EXPECT_TRUE(anonymous.close);
  EXPECT_TRUE(ws.handle(R"({"type":"ping","request_id":2})", anonymous).empty()) << "nothing after the refusal";

  WsConnection wrong = connect();
  expect_one_error(ws.handle(R"({"type":"auth","token":"cgv_0000000000000000_nope","request_id":1})", wrong),
                   "unauthorized");
  EXPECT_TRUE(wrong.close);

  WsConnection alice = connect();
  auto replies = ws.handle(R"({"type":"auth","token":")" + alice_ + R"(","request_id":1})", alice);
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(parse(replies[0]),
            json({{"type", "authenticated"}, {"request_id", 1}, {"user", "alice"}, {"admin", false}}));
  replies = ws.handle(R"({"type":"list_meshes","request_id":2})", alice);
  ASSERT_EQ(replies.size(), 1u);
  const json list = parse(replies[0]);
  ASSERT_EQ(list["meshes"].size(), 1u) << list;
  EXPECT_EQ(list["meshes"][0]["id"], alices.id);
  expect_one_error(ws.handle(R"({"type":"get_mesh","request_id":3,"mesh_id":")" + bobs.id + R"("})", alice),
                   "not_found");

  // Events go to their readers only.
  std::vector<WsOut> sent;
  const WsEmit emit = [&](WsOut o) { sent.push_back(std::move(o)); };
  EXPECT_TRUE(ws.admits_event(alice, Access{"alice"}, emit));
  EXPECT_FALSE(ws.admits_event(alice, Access{"bob"}, emit));
  EXPECT_TRUE(sent.empty());

  // A token given in the upgrade's header, revoked while the connection is open.
  WsConnection by_header = connect("Bearer " + alice_);
  ASSERT_TRUE(by_header.caller);
  store_->revoke_tokens("alice");
  EXPECT_FALSE(ws.admits_event(by_header, Access{"alice"}, emit));
  const json revoked = expect_one_error(sent, "unauthorized");
  EXPECT_NE(revoked["detail"].get<std::string>().find("revoked"), std::string::npos);
  EXPECT_TRUE(by_header.close);
  expect_one_error(ws.handle(R"({"type":"ping","request_id":4})", alice), "unauthorized");
  EXPECT_TRUE(alice.close);

  // Revoked by another process (the CLI's `user revoke`: another connection to
  // the database), after events were admitted from the checked caller: the
  // next event sees it.
  WsConnection bobs_socket = connect("Bearer " + bob_);
  ASSERT_TRUE(bobs_socket.caller);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(ws.admits_event(bobs_socket, Access{"bob"}, emit));
  Store(dir_ / "data").revoke_tokens("bob");
  sent.clear();
  EXPECT_FALSE(ws.admits_event(bobs_socket, Access{"bob"}, emit));
  expect_one_error(sent, "unauthorized");
}

TEST_F(WsHandlerTest, OverTheRateLimitAMessageIsRefusedWithRetryAfter) {
  open_local();
  RateLimiter rate(0.5, 2);
  int refused = 0;
  rate.on_refused = [&] { ++refused; };
  const WsHandler ws = handler(&rate);
  WsConnection remote = connect("", "192.0.2.7");
  remote.caller = Caller::local();
  for (int i = 0; i < 2; ++i) EXPECT_EQ(parse(ws.handle(R"({"type":"ping"})", remote).at(0))["type"], "pong");
  const json e = expect_one_error(ws.handle(R"({"type":"ping","request_id":3})", remote), "rate_limited");
  EXPECT_EQ(e["request_id"], 3);
  EXPECT_GE(e["retry_after_s"].get<int>(), 1);
  EXPECT_EQ(refused, 1);
  EXPECT_FALSE(remote.close);
  // The local user (loopback, no token) is not limited.
  WsConnection local = connect();
  for (int i = 0; i < 5; ++i) EXPECT_EQ(parse(ws.handle(R"({"type":"ping"})", local).at(0))["type"], "pong");
}

// The payload of a slice reply: its frames joined; checks they follow the slice message.
std::string slice_payload(const std::vector<WsOut>& replies, std::uint32_t request_id) {
  std::string payload;
  for (std::size_t i = 1; i + 1 < replies.size(); ++i) {
    std::string_view chunk;
    const std::string frame = replies[i].head + std::string(replies[i].body);
    EXPECT_EQ(protocol::decode_frame(frame, &chunk).request_id, request_id);
    payload += chunk;
  }
  return payload;
}

TEST_F(WsHandlerTest, SlicesOfAGridKeptDecodedServeOnlyThoseWhoMayReadTheJob) {
  make_dir("ws-");
  open_with_users(dir_ / "data", JobConfig{});
  const Caller alice = *router_->auth().authenticate("Bearer " + alice_);
  const MeshRecord cube = meshes_->upload("cube.off", "", test::read_bytes(test::sample("cube.off")), "alice");
  const std::string id = jobs_->submit(
      {{"algorithm", "voxelize"}, {"inputs", {{"mesh", cube.id}}}, {"params", {{"resolution", 16}, {"mode", "solid"}}}},
      alice)["id"];
  for (int i = 0; i < 600 && jobs_->get(id, alice)->value("state", "") != "done"; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_EQ(jobs_->get(id, alice)->value("state", ""), "done") << *jobs_->get(id, alice);
  const WsHandler ws(*meshes_,
                     {[this](const std::string& job, const std::string& name, const std::string& format,
                             const Caller& c) { return jobs_->artifact(job, name, format, c); },
                      [this](const std::string& job, const Caller& c) { (void)jobs_->access(job, c); }},
                     router_->auth(), nullptr, {64, 1024});
  // The reference: the grid file as the job wrote it, sliced here.
  const VoxelGrid grid = decode_nrrd(jobs_->artifact(id, "grid", "nrrd", alice).bytes);
  const int k = grid.dims()[2] / 2;
  const VoxelSlice expected = slice(grid, 2, k);
  const std::string request =
      R"({"type":"get_slice","request_id":5,"axis":"z","index":)" + std::to_string(k) + R"(,"job_id":")" + id + R"("})";
  WsConnection a = connect("Bearer " + alice_);
  std::string first;
  for (int round = 0; round < 2; ++round) {  // read and decoded, then kept
    SCOPED_TRACE(round);
    const auto replies = ws.handle(request, a);
    ASSERT_GE(replies.size(), 3u);
    const json head = parse(replies[0]);
    EXPECT_EQ(head["type"], "slice") << head;
    EXPECT_EQ(head["width"], expected.width);
    EXPECT_EQ(head["height"], expected.height);
    const std::string payload = slice_payload(replies, 5);
    EXPECT_EQ(protocol::decode_slice_payload(payload).slice.values, expected.values);
    if (round == 0) first = payload;
    else EXPECT_EQ(payload, first);
  }
  // Bob does not read Alice's job, kept or not; once she shares it, he does.
  WsConnection b = connect("Bearer " + bob_);
  expect_one_error(ws.handle(request, b), "not_found");
  store_->set_shared("job", id, {"bob"}, true);
  const auto shared = ws.handle(request, b);
  ASSERT_GE(shared.size(), 3u);
  EXPECT_EQ(slice_payload(shared, 5), first);
  store_->set_shared("job", id, {"bob"}, false);
  expect_one_error(ws.handle(request, b), "not_found");
}

}  // namespace
}  // namespace cgview::server
