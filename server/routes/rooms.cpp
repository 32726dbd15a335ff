// /api/v1/courses/{id}/rooms and /api/v1/rooms/{id}/recording: a course's
// live lectures and their recordings (teaching/rooms.h); the rooms
// themselves are WebSocket messages (ws_handler.cpp).
#include "router.h"
#include "routes/routes.h"
#include "teaching/rooms.h"

namespace cgview::server {

namespace {

Rooms& rooms(const RouteContext& ctx) {
  if (!ctx.config.rooms) throw std::runtime_error("this server holds no live rooms");
  return *ctx.config.rooms;
}

}  // namespace

void add_room_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back({"GET",
                    "/api/v1/courses/{id}/rooms",
                    "A course's live lectures, live and recorded (its members)",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(200, rooms(ctx).list(p.at("id"), caller));
                    },
                    false});
  routes.push_back({"GET",
                    "/api/v1/rooms/{id}/recording",
                    "A lecture's recording: its state changes with their times, to replay as live 3D",
                    {},
                    [&ctx](const Params& p, const HttpRequest&, const Caller& caller) {
                      return json_response(200, rooms(ctx).recording(p.at("id"), caller));
                    }});
}

}  // namespace cgview::server
