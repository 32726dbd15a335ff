// A live lecture on the real server, over real WebSockets: a teacher
// presents to a course, followers get each change and a late one the whole
// state, the camera is coalesced with its latest value last, what the
// teacher shows is readable by the followers while the room lasts (and no
// longer), a follower cannot write, a raised hand reaches the teacher and is
// shown to all, and the recording replays every change in order.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "server_harness.h"
#include "test_support.h"

namespace cgview::test {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

class Rooms : public ServerFixture {
 protected:
  Rooms() : ServerFixture("rooms-") {}
  void SetUp() override {
    ServerFixture::SetUp();
    teacher_ = server_command(data_, "user add tina --role teacher");
    alice_ = server_command(data_, "user add alice");
    bob_ = server_command(data_, "user add bob");
    eve_ = server_command(data_, "user add eve");
    ASSERT_TRUE(server_.start(data_, {"--auth", "required"}, dir_));
    const HttpResult c = as(teacher_, "POST", "/api/v1/courses", {{"title", "Lecture"}});
    ASSERT_EQ(c.status, 201u) << c.body;
    course_ = c.body_json().value("id", "");
    ASSERT_EQ(as(teacher_, "POST", "/api/v1/courses/" + course_ + "/members", json::array({"alice", "bob"})).status,
              200u);
  }
  HttpResult as(const std::string& token, const std::string& method, const std::string& target,
                const json& body = nullptr) {
    return call_as(port(), token, method, target, body.is_null() ? "" : body.dump());
  }
  // A signed-in WebSocket.
  std::unique_ptr<WsClient> connect(const std::string& token) {
    auto ws = std::make_unique<WsClient>();
    EXPECT_FALSE(ws->connect(port()));
    EXPECT_FALSE(ws->send({{"type", "auth"}, {"token", token}, {"request_id", 0}}));
    EXPECT_EQ(ws->reply().value("type", ""), "authenticated");
    return ws;
  }
  // The next message of `type` (others, such as presence, skipped).
  static json next(WsClient& ws, const std::string& type) {
    for (;;) {
      const auto m = ws.read(10s);
      if (!m) {
        ADD_FAILURE() << "no " << type << ": " << ws.last_error().message();
        return json();
      }
      json j = json::parse(m->data, nullptr, false);
      if (j.value("type", "") == type || j.value("type", "") == "error") return j;
    }
  }
  std::string teacher_, alice_, bob_, eve_, course_;
};

TEST_F(Rooms, FollowersMirrorThePresenterAndTheLectureReplays) {
  const std::string mesh = [&] {
    const HttpResult up =
        call_as(port(), teacher_, "POST", "/api/v1/meshes?name=cube.off", read_bytes(sample("cube.off")));
    return up.body_json().value("id", "");
  }();
  EXPECT_EQ(as(alice_, "GET", "/api/v1/meshes/" + mesh).status, 404u);  // the teacher's own, unshared

  auto teacher = connect(teacher_);
  ASSERT_FALSE(teacher->send({{"type", "present"}, {"course", course_}, {"request_id", 1}}));
  const json room = next(*teacher, "room");
  ASSERT_EQ(room.value("role", ""), "presenter") << room.dump();
  const std::string id = room["room"];
  // A student cannot present to the course.
  auto alice = connect(alice_);
  ASSERT_FALSE(alice->send({{"type", "present"}, {"course", course_}, {"request_id", 1}}));
  EXPECT_EQ(next(*alice, "room").value("error", ""), "forbidden");

  ASSERT_FALSE(alice->send({{"type", "follow"}, {"room", id}, {"request_id", 2}}));
  const json joined = next(*alice, "room_state");
  EXPECT_EQ(joined["state"], json::object()) << joined.dump();
  EXPECT_EQ(next(*teacher, "room_presence").value("followers", 0), 1);

  // The teacher shows their mesh and drags the camera: twenty changes at once.
  ASSERT_FALSE(
      teacher->send({{"type", "room_set"}, {"room", id}, {"part", "meshes"}, {"value", {{"meshes", {mesh}}}}}));
  EXPECT_EQ(next(*alice, "room_update").value("part", ""), "meshes");
  for (int i = 1; i <= 20; ++i)
    ASSERT_FALSE(teacher->send(
        {{"type", "room_set"}, {"room", id}, {"part", "camera"}, {"value", {{"azimuth", i}, {"elevation", 10}}}}));
  int updates = 0;
  json last = json::object();
  while (last.value("azimuth", 0) != 20) {
    const json u = next(*alice, "room_update");
    ASSERT_EQ(u.value("part", ""), "camera") << u.dump();
    last = u["value"];
    ++updates;
  }
  EXPECT_LT(updates, 20) << "coalesced at up to 30 a second";
  // What the teacher shows, the followers read while the room lasts; others do not.
  EXPECT_EQ(as(alice_, "GET", "/api/v1/meshes/" + mesh).status, 200u);
  EXPECT_EQ(as(eve_, "GET", "/api/v1/meshes/" + mesh).status, 404u);

  // A follower cannot write; a non-member cannot follow.
  ASSERT_FALSE(alice->send({{"type", "room_set"}, {"room", id}, {"part", "camera"}, {"value", 1}, {"request_id", 3}}));
  EXPECT_EQ(next(*alice, "error").value("error", ""), "forbidden");
  auto eve = connect(eve_);
  ASSERT_FALSE(eve->send({{"type", "follow"}, {"room", id}, {"request_id", 1}}));
  EXPECT_EQ(next(*eve, "room_state").value("error", ""), "not_found");

  // A late follower gets the whole state at once.
  auto bob = connect(bob_);
  ASSERT_FALSE(bob->send({{"type", "follow"}, {"room", id}, {"request_id", 1}}));
  const json late = next(*bob, "room_state");
  EXPECT_EQ(late["state"]["camera"].value("azimuth", 0), 20) << late.dump();
  EXPECT_EQ(late["state"]["meshes"]["meshes"], json({mesh}));

  // Alice raises her hand on a point; the teacher sees it and shows it to all.
  const json point = {{"mesh", mesh}, {"position", {0.5, 0.5, 1.0}}};
  ASSERT_FALSE(alice->send({{"type", "raise_hand"}, {"room", id}, {"point", point}}));
  json presence;
  do presence = next(*teacher, "room_presence");
  while (presence["hands"].empty());
  EXPECT_EQ(presence["hands"][0].value("user", ""), "alice");
  EXPECT_EQ(presence.value("followers", 0), 2);
  ASSERT_FALSE(teacher->send({{"type", "show_hand"}, {"room", id}, {"user", "alice"}}));
  const json shown = next(*bob, "room_update");
  EXPECT_EQ(shown.value("part", ""), "hand");
  EXPECT_EQ(shown["value"]["point"], point);

  // Alice leaves: no longer counted, her hand lowered; she cannot leave twice.
  ASSERT_FALSE(alice->send({{"type", "leave"}, {"room", id}}));
  do presence = next(*teacher, "room_presence");
  while (presence.value("followers", 0) != 1);
  EXPECT_TRUE(presence["hands"].empty()) << presence.dump();
  ASSERT_FALSE(alice->send({{"type", "leave"}, {"room", id}, {"request_id", 4}}));
  EXPECT_EQ(next(*alice, "error").value("error", ""), "not_found");
  ASSERT_FALSE(alice->send({{"type", "follow"}, {"room", id}, {"request_id", 5}}));
  EXPECT_EQ(next(*alice, "room_state").value("room", ""), id);

  // The end: followers are told, and the mesh is the teacher's alone again.
  ASSERT_FALSE(teacher->send({{"type", "room_end"}, {"room", id}}));
  EXPECT_EQ(next(*alice, "room_ended").value("room", ""), id);
  EXPECT_EQ(next(*bob, "room_ended").value("room", ""), id);
  EXPECT_EQ(as(alice_, "GET", "/api/v1/meshes/" + mesh).status, 404u);

  // The recording: every change, in order, for the course's members.
  const HttpResult rec = as(alice_, "GET", "/api/v1/rooms/" + id + "/recording");
  ASSERT_EQ(rec.status, 200u) << rec.body;
  const json events = rec.body_json()["events"];
  ASSERT_GE(events.size(), 3u);
  EXPECT_EQ(events.front().value("part", ""), "meshes");
  EXPECT_EQ(events.back().value("part", ""), "hand");
  json camera;
  std::int64_t t = -1;
  for (const json& e : events) {
    EXPECT_GE(e.value("t_ms", std::int64_t(-1)), t);
    t = e.value("t_ms", std::int64_t(-1));
    if (e["part"] == "camera") camera = e["value"];
  }
  EXPECT_EQ(camera.value("azimuth", 0), 20);
  EXPECT_EQ(as(eve_, "GET", "/api/v1/rooms/" + id + "/recording").status, 404u);
  const json listed = as(bob_, "GET", "/api/v1/courses/" + course_ + "/rooms").body_json();
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_FALSE(listed[0].value("live", true));
}

TEST_F(Rooms, AJoinCodeRoomIsFollowedByItsCodeAndEndsWithItsPresentersSocket) {
  auto teacher = connect(teacher_);
  ASSERT_FALSE(teacher->send({{"type", "present"}, {"code", true}, {"request_id", 1}}));
  const json room = next(*teacher, "room");
  const std::string code = room.value("code", "");
  ASSERT_FALSE(code.empty()) << room.dump();
  auto eve = connect(eve_);  // in no course: the code is enough
  ASSERT_FALSE(eve->send({{"type", "follow"}, {"code", "wrong"}, {"request_id", 1}}));
  EXPECT_EQ(next(*eve, "room_state").value("error", ""), "not_found");
  ASSERT_FALSE(eve->send({{"type", "follow"}, {"code", code}, {"request_id", 2}}));
  EXPECT_EQ(next(*eve, "room_state").value("room", ""), room.value("room", ""));
  teacher->abort();  // the presenter's connection drops
  EXPECT_EQ(next(*eve, "room_ended").value("room", ""), room.value("room", ""));
}

}  // namespace
}  // namespace cgview::test
