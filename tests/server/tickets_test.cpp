// Sign-in tickets (server/tickets.h, routes/tickets.cpp) through the router,
// no sockets: a token's holder gets a ticket; the ticket, redeemed once and
// without a token, is a session of the same user that works wherever a token
// does, until it expires or its token is revoked; a used, expired or forged
// ticket is 401; a session makes no tickets; only hashes are kept.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <fstream>
#include <sstream>

#include "auth.h"
#include "router_harness.h"
#include "router.h"
#include "store.h"
#include "tickets.h"

namespace cgview::server {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

class TicketsTest : public test::RouterFixture {
 protected:
  void SetUp() override {
    make_dir("tickets-");
    open(dir_, std::nullopt, [] {
      RouterConfig rc;
      rc.auth_required = true;
      return rc;
    }());
    Auth auth(*store_, true);
    alice_ = auth.add_user("alice", false);
    bob_ = auth.add_user("bob", false);
    // The tickets' clock: the real one plus what a test adds.
    router_->auth().set_ticket_clock([this] { return std::chrono::steady_clock::now() + skew_.load(); });
  }

  HttpResponse call(const std::string& token, const std::string& method, const std::string& target,
                    std::string body = "") {
    return router_->handle({method, target, std::move(body), token.empty() ? "" : "Bearer " + token});
  }

  // A ticket of `token`'s (expires_s: the body's, if any).
  std::string ticket(const std::string& token, const std::string& body = "") {
    const HttpResponse r = call(token, "POST", "/api/v1/tickets", body);
    EXPECT_EQ(r.status, 200) << r.body;
    return json::parse(r.body).value("ticket", "");
  }

  // Redeems a ticket with no token, as the viewer does.
  HttpResponse redeem(const std::string& ticket) {
    return call("", "POST", "/api/v1/tickets/redeem", json{{"ticket", ticket}}.dump());
  }

  static void expect_unauthorized(const HttpResponse& r) {
    EXPECT_EQ(r.status, 401) << r.body;
    EXPECT_EQ(json::parse(r.body).value("error", ""), "unauthorized");
  }

  std::atomic<std::chrono::steady_clock::duration> skew_{std::chrono::steady_clock::duration::zero()};
};

TEST_F(TicketsTest, ATicketIsRedeemedOnceForASessionOfItsUser) {
  const HttpResponse made = call(alice_, "POST", "/api/v1/tickets");
  ASSERT_EQ(made.status, 200) << made.body;
  const json t = json::parse(made.body);
  EXPECT_EQ(t["expires_s"], 60);
  const std::string ticket = t["ticket"];
  // cgt_ID_SECRET: not a token, refused as one.
  ASSERT_EQ(ticket.size(), 4u + 16 + 1 + 64);
  EXPECT_EQ(ticket.substr(0, 4), "cgt_");
  expect_unauthorized(call(ticket, "GET", "/api/v1/me"));

  const HttpResponse redeemed = redeem(ticket);
  ASSERT_EQ(redeemed.status, 200) << redeemed.body;
  const json s = json::parse(redeemed.body);
  EXPECT_EQ(s["user"], "alice");
  EXPECT_EQ(s["expires_s"], 8 * 3600);
  const std::string session = s["token"];
  EXPECT_EQ(session.size(), alice_.size());
  EXPECT_NE(session, alice_);
  // The session is alice wherever a token is taken: REST and the WebSocket's auth.
  const HttpResponse me = call(session, "GET", "/api/v1/me");
  ASSERT_EQ(me.status, 200) << me.body;
  EXPECT_EQ(json::parse(me.body)["user"], "alice");
  ASSERT_TRUE(router_->auth().authenticate("Bearer " + session));
  EXPECT_EQ(router_->auth().authenticate("Bearer " + session)->user, "alice");
  // Once only.
  expect_unauthorized(redeem(ticket));
  // Another user's ticket is that user's.
  const HttpResponse bob = redeem(this->ticket(bob_));
  ASSERT_EQ(bob.status, 200) << bob.body;
  EXPECT_EQ(json::parse(call(json::parse(bob.body)["token"], "GET", "/api/v1/me").body)["user"], "bob");
}

TEST_F(TicketsTest, ForgedMalformedAndMissingTicketsAre401) {
  const std::string ticket = this->ticket(alice_);
  std::string forged = ticket;
  forged.back() = forged.back() == '0' ? '1' : '0';
  expect_unauthorized(redeem(forged));
  // Tried once with the wrong secret, the ticket is gone: its secret is not guessed by trying.
  expect_unauthorized(redeem(ticket));
  expect_unauthorized(redeem("cgt_0123456789abcdef_" + std::string(64, '0')));
  expect_unauthorized(redeem(alice_));  // a token is not a ticket
  expect_unauthorized(redeem("nonsense"));
  expect_unauthorized(call("", "POST", "/api/v1/tickets/redeem", "{}"));
  expect_unauthorized(call("", "POST", "/api/v1/tickets/redeem", "not json"));
  expect_unauthorized(call("", "POST", "/api/v1/tickets/redeem", R"({"ticket":7})"));
  // Making one needs a token.
  expect_unauthorized(call("", "POST", "/api/v1/tickets"));
}

TEST_F(TicketsTest, ATicketExpires) {
  const std::string ticket = this->ticket(alice_);
  skew_ = 61s;
  expect_unauthorized(redeem(ticket));
  // A shorter life when asked; out of [1, 60] is a 400.
  skew_ = 0s;
  const HttpResponse made = call(alice_, "POST", "/api/v1/tickets", R"({"expires_s":5})");
  ASSERT_EQ(made.status, 200) << made.body;
  EXPECT_EQ(json::parse(made.body)["expires_s"], 5);
  skew_ = 6s;
  expect_unauthorized(redeem(json::parse(made.body)["ticket"]));
  for (const char* body :
       {R"({"expires_s":0})", R"({"expires_s":61})", R"({"expires_s":"5"})", R"({"expires_s":1.5})", "[1]"}) {
    const HttpResponse r = call(alice_, "POST", "/api/v1/tickets", body);
    EXPECT_EQ(r.status, 400) << body << " " << r.body;
    EXPECT_EQ(json::parse(r.body)["error"], "bad_request");
  }
}

TEST_F(TicketsTest, ASessionExpiresAndEndsWithItsToken) {
  const std::string session = json::parse(redeem(ticket(alice_)).body)["token"];
  EXPECT_EQ(call(session, "GET", "/api/v1/me").status, 200);
  skew_ = Tickets::kSessionLife + 1s;
  expect_unauthorized(call(session, "GET", "/api/v1/me"));
  EXPECT_FALSE(router_->auth().authenticate("Bearer " + session));
  // Revoking the token ends its sessions at once.
  skew_ = 0s;
  const std::string second = json::parse(redeem(ticket(alice_)).body)["token"];
  EXPECT_EQ(call(second, "GET", "/api/v1/me").status, 200);
  const std::string ticket_before = ticket(alice_);
  store_->revoke_tokens("alice");
  expect_unauthorized(call(second, "GET", "/api/v1/me"));
  expect_unauthorized(redeem(ticket_before));  // nor does a ticket made before outlive it
  EXPECT_EQ(call(bob_, "GET", "/api/v1/me").status, 200);
}

TEST_F(TicketsTest, ASessionMakesNoTickets) {
  const std::string session = json::parse(redeem(ticket(alice_)).body)["token"];
  const HttpResponse r = call(session, "POST", "/api/v1/tickets");
  EXPECT_EQ(r.status, 403) << r.body;
  EXPECT_EQ(json::parse(r.body)["error"], "forbidden");
}

TEST_F(TicketsTest, OnLoopbackWithoutATokenThereIsNoTicketToMake) {
  Router open(*meshes_, RouterConfig{});
  const HttpResponse r = open.handle({"POST", "/api/v1/tickets", "", ""});
  EXPECT_EQ(r.status, 400) << r.body;
  // With a token it works there too, for the viewer of a script that has one.
  const HttpResponse made = open.handle({"POST", "/api/v1/tickets", "", "Bearer " + alice_});
  ASSERT_EQ(made.status, 200) << made.body;
  const HttpResponse s =
      open.handle({"POST", "/api/v1/tickets/redeem", json{{"ticket", json::parse(made.body)["ticket"]}}.dump(), ""});
  ASSERT_EQ(s.status, 200) << s.body;
  EXPECT_EQ(json::parse(s.body)["user"], "alice");
}

// Tickets and sessions, as tokens: only the SHA-256 of a secret is kept, and
// nothing of either reaches the store's file.
TEST_F(TicketsTest, SecretsAreNotKept) {
  const std::string ticket = this->ticket(alice_);
  Tickets tickets;
  const std::string other = tickets.issue({"alice", alice_.substr(4, 16)});
  const auto session = tickets.redeem(other);
  ASSERT_TRUE(session);
  EXPECT_TRUE(tickets.session(session->token.substr(4, 16), session->token.substr(21)));
  EXPECT_FALSE(tickets.session(session->token.substr(4, 16), std::string(64, '0')));
  const std::string session_token = json::parse(redeem(ticket).body)["token"];
  std::ifstream db(dir_ / "cgview.db", std::ios::binary);
  std::stringstream bytes;
  bytes << db.rdbuf();
  EXPECT_EQ(bytes.str().find(ticket.substr(21)), std::string::npos);
  EXPECT_EQ(bytes.str().find(session_token.substr(21)), std::string::npos);
}

}  // namespace
}  // namespace cgview::server
