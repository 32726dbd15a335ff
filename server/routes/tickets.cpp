// /api/v1/tickets: sign-in tickets (tickets.h).  A script with a token asks
// for one and hands it to a page (the viewer in a notebook's output cell),
// which redeems it, once, for a session credential: no token in any URL.
#include "routes/routes.h"

#include "io/parse_json.h"
#include "router.h"
#include "teaching/courses.h"

namespace cgview::server {

using nlohmann::json;

namespace {

HttpResponse unauthorized(const std::string& detail) {
  HttpResponse r = error_response(401, "unauthorized", detail);
  r.headers.push_back({"WWW-Authenticate", "Bearer"});
  return r;
}

}  // namespace

void add_ticket_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back(
      {"POST",
       "/api/v1/tickets",
       "A sign-in ticket for your token: {\"ticket\", \"expires_s\"}, redeemed once within expires_s (body: "
       "{\"expires_s\": 1..60}, default 60)",
       {},
       [&ctx](const Params&, const HttpRequest& req, const Caller&) {
         const json body = req.body.empty() ? json::object() : parse_json_or_discarded(req.body);
         if (!body.is_object()) return error_response(400, "bad_request", "the body is not a JSON object");
         const auto max_life = Tickets::kTicketLife.count();
         std::chrono::seconds life = Tickets::kTicketLife;
         if (body.contains("expires_s")) {
           const json& v = body["expires_s"];
           if (!v.is_number_integer() || v.get<long long>() < 1 || v.get<long long>() > max_life)
             return error_response(400, "bad_request",
                                   "expires_s must be an integer in [1, " + std::to_string(max_life) + "]");
           life = std::chrono::seconds(v.get<long long>());
         }
         if (req.authorization.empty())
           return error_response(400, "bad_request",
                                 "a ticket stands for a token, and this request carried none (a server on loopback "
                                 "needs neither)");
         const auto ticket = ctx.auth->issue_ticket(req.authorization, life);
         if (!ticket)
           return error_response(403, "forbidden", "a session signed in with a ticket makes no tickets: use a token");
         return json_response(200, {{"ticket", *ticket}, {"expires_s", life.count()}});
       },
       false});
  // Needs no token (the ticket is the credential): Router::dispatch lets it through.
  routes.push_back(
      {"POST",
       "/api/v1/tickets/redeem",
       "Redeem a ticket, once, for a session credential of its user: body {\"ticket\"} → "
       "{\"token\", \"user\", \"expires_s\"}; a used, expired or forged ticket is 401",
       {},
       [&ctx](const Params&, const HttpRequest& req, const Caller&) {
         const json body = parse_json_or_discarded(req.body);
         const json* ticket = body.is_object() && body.contains("ticket") ? &body["ticket"] : nullptr;
         if (!ticket || !ticket->is_string()) return unauthorized("no ticket: the body is {\"ticket\": \"cgt_…\"}");
         // A course's sign-in link (teaching/courses.h) gives its student a token of their own, kept by the page.
         if (ticket->get<std::string>().starts_with("cgl_")) {
           const auto user =
               ctx.config.courses ? ctx.config.courses->redeem_link(ticket->get<std::string>()) : std::nullopt;
           if (!user) return unauthorized("the sign-in link is wrong, used or expired: ask your teacher for another");
           return json_response(200, {{"token", ctx.auth->new_token(*user)}, {"user", *user}, {"kind", "token"}});
         }
         const auto session = ctx.auth->redeem_ticket(ticket->get<std::string>());
         if (!session) return unauthorized("the ticket is wrong, used or expired: ask for another");
         return json_response(
             200, {{"token", session->token}, {"user", session->grant.user}, {"expires_s", session->life.count()}});
       },
       false});
}

}  // namespace cgview::server
