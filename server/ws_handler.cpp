#include "ws_handler.h"

#include <climits>
#include <set>

#include "animation_frames.h"
#include "core/errors.h"
#include "io/parse_json.h"
#include "mesh_service.h"
#include "rate_limit.h"
#include "teaching/rooms.h"
#include "io/zip_bundle.h"  // TooLarge
#include "voxel/voxel_io.h"
#include "voxel_slice.h"

namespace cgview::server {

using nlohmann::json;

namespace {

json error_message(const json& request_id, const std::string& code, const std::string& detail) {
  return {{"type", "error"}, {"request_id", request_id}, {"error", code}, {"detail", detail}};
}

// The string field `name` of a message, or nullopt.
std::optional<std::string> string_field(const json& msg, const char* name) {
  if (!msg.contains(name) || !msg[name].is_string()) return std::nullopt;
  return msg[name].get<std::string>();
}

}  // namespace

WsOut WsOut::text(const json& message) {
  return {message.dump(-1, ' ', false, json::error_handler_t::replace), nullptr, {}, false};
}

WsHandler::WsHandler(MeshService& meshes, JobArtifacts artifacts, const Auth& auth, RateLimiter* rate,
                     WsHandlerConfig config)
    : meshes_(meshes), artifacts_(std::move(artifacts)), auth_(auth), rate_(rate), config_(config) {}

WsOut WsHandler::too_big() const {
  return WsOut::text(
      error_message(nullptr, "payload_too_large",
                    "messages to the server are limited to " + std::to_string(config_.max_message_bytes) + " bytes"));
}

std::optional<Caller> WsHandler::still_authorized(WsConnection& conn, const WsEmit& emit) const {
  if (conn.close || !conn.caller) return std::nullopt;
  if (conn.authorization.empty()) return conn.caller;  // the local user
  // Read again at each use: a revoked token ends the session, and a member
  // removed from a course reads what it shares no more.
  if (auto fresh = auth_.authenticate(conn.authorization)) return fresh;
  emit(WsOut::text(error_message(nullptr, "unauthorized", "the token was revoked")));
  conn.close = true;
  return std::nullopt;
}

bool WsHandler::admits_event(WsConnection& conn, const Access& readers, const WsEmit& emit) const {
  if (conn.close || !conn.caller) return false;
  const std::int64_t version = meshes_.store().version();
  const auto now = std::chrono::steady_clock::now();
  if (!conn.checked || conn.checked_version != version || now - conn.checked_at >= std::chrono::seconds(1)) {
    conn.checked = still_authorized(conn, emit);
    conn.checked_version = version;
    conn.checked_at = now;
  }
  return conn.checked && readers.allows(*conn.checked);
}

WsHandler::Work WsHandler::receive(std::string_view text, bool binary, WsConnection& conn, const WsEmit& emit) const {
  auto error = [&](const json& id, const std::string& code, const std::string& detail) {
    emit(WsOut::text(error_message(id, code, detail)));
    return Work();
  };
  // A missing or wrong token: one error, then the connection closes.
  auto refuse = [&](const json& id, const std::string& detail) {
    conn.close = true;
    return error(id, "unauthorized", detail);
  };
  if (conn.close) return {};
  if (binary) return error(nullptr, "bad_request", "binary messages are not accepted; send JSON text");
  json msg;
  try {
    msg = parse_json(text, "the message");
  } catch (const json::exception&) {
    return error(nullptr, "bad_request", "the message is not JSON");
  } catch (const InvalidInput& e) {
    return error(nullptr, "bad_request", e.what());
  }
  if (!msg.is_object()) return error(nullptr, "bad_request", "the message must be a JSON object");
  const json id = msg.contains("request_id") ? msg["request_id"] : json(nullptr);
  if (!id.is_null() && !id.is_number_unsigned())
    return error(nullptr, "bad_request", "request_id must be a non-negative integer");
  const auto type = string_field(msg, "type");
  if (!type) return error(id, "bad_request", "the message has no \"type\"");
  // A presenter's stream is not held back by the per-token rate limit: a
  // camera dragged sends 30 changes a second (the room coalesces them).
  const bool presenting = *type == "room_set" && rooms_ && conn.caller && msg.value("room", json()).is_string() &&
                          rooms_->presents(msg["room"], conn.caller->user);
  if (rate_ && !presenting) {
    if (const auto over = check_rate(*rate_, conn.authorization, conn.address, conn.loopback)) {
      json refusal = error_message(id, "rate_limited", over->detail);
      refusal["retry_after_s"] = over->retry_after_s;
      emit(WsOut::text(refusal));
      return {};
    }
  }
  if (*type == "auth") {
    const json token = msg.value("token", json());
    conn.authorization =
        token.is_string() && !token.get<std::string>().empty() ? "Bearer " + token.get<std::string>() : "-";
    conn.caller = auth_.authenticate(conn.authorization);
    if (!conn.caller) return refuse(id, "the token is wrong or was revoked");
    emit(WsOut::text(
        {{"type", "authenticated"}, {"request_id", id}, {"user", conn.caller->user}, {"admin", conn.caller->admin}}));
    return {};
  }
  if (!conn.caller) return refuse(id, "this server needs a token: send {\"type\":\"auth\",\"token\":TOKEN} first");
  const auto caller = still_authorized(conn, emit);
  if (!caller) return {};
  if (*type == "ping") {
    emit(WsOut::text({{"type", "pong"}, {"request_id", id}}));
    return {};
  }
  if (room_message(*type, msg, id, conn, *caller, emit)) return {};
  using Part = void (WsHandler::*)(const json&, const json&, const Caller&, const WsEmit&) const;
  Part part = nullptr;
  if (*type == "get_mesh") part = &WsHandler::get_mesh;
  else if (*type == "get_slice") part = &WsHandler::get_slice;
  else if (*type == "get_animation") part = &WsHandler::get_animation;
  else if (*type != "list_meshes") return error(id, "bad_request", "unknown message type '" + *type + "'");
  return [this, part, msg = std::move(msg), id, caller = *caller](const WsEmit& out) {
    try {
      if (part) return (this->*part)(msg, id, caller, out);
      json list = json::array();
      for (const auto& r : meshes_.store().list_meshes(caller)) list.push_back(mesh_json(r));
      out(WsOut::text({{"type", "meshes"}, {"request_id", id}, {"meshes", list}}));
    } catch (const InvalidInput& e) {
      out(WsOut::text(error_message(id, "bad_request", e.what())));
    } catch (const std::exception& e) {
      out(WsOut::text(error_message(id, "internal", e.what())));
    }
  };
}

bool WsHandler::room_message(const std::string& type, const json& msg, const json& id, WsConnection& conn,
                             const Caller& caller, const WsEmit& emit) const {
  static const std::set<std::string> kinds = {"present",    "follow",    "leave",   "room_set",
                                              "raise_hand", "show_hand", "room_end"};
  if (!kinds.count(type)) return false;
  try {
    if (!rooms_) throw std::runtime_error("this server holds no live rooms");
    if (conn.id.empty()) conn.id = new_id();
    const auto room = string_field(msg, "room");
    auto need_room = [&] {
      if (!room) throw InvalidInput("the message has no \"room\"");
      return *room;
    };
    json reply;
    if (type == "present") reply = rooms_->present(msg, caller, conn.id);
    else if (type == "follow") reply = rooms_->follow(msg, caller, conn.id);
    else if (type == "leave") rooms_->leave(need_room(), caller, conn.id);
    else if (type == "room_set") {
      const auto part = string_field(msg, "part");
      if (!part || !msg.contains("value")) throw InvalidInput("room_set is {\"room\", \"part\", \"value\"}");
      rooms_->set(need_room(), *part, msg["value"], caller);
    } else if (type == "raise_hand") {
      rooms_->hand(need_room(), msg.value("point", json()), caller);
    } else if (type == "show_hand") {
      const auto user = string_field(msg, "user");
      if (!user) throw InvalidInput("show_hand is {\"room\", \"user\"}");
      rooms_->show_hand(need_room(), *user, caller);
    } else {
      rooms_->end(need_room(), caller);
    }
    if (!reply.is_null()) {
      reply["request_id"] = id;
      emit(WsOut::text(reply));
    }
  } catch (const Forbidden& e) {
    emit(WsOut::text(error_message(id, "forbidden", e.what())));
  } catch (const TooLarge& e) {
    emit(WsOut::text(error_message(id, "payload_too_large", e.what())));
  } catch (const InvalidInput& e) {
    emit(WsOut::text(error_message(id, "bad_request", e.what())));
  } catch (const std::out_of_range& e) {
    emit(WsOut::text(error_message(id, "not_found", e.what())));
  } catch (const std::exception& e) {
    emit(WsOut::text(error_message(id, "internal", e.what())));
  }
  return true;
}

void WsHandler::closed(const WsConnection& conn) const {
  if (rooms_ && !conn.id.empty()) rooms_->disconnected(conn.id);
}

std::vector<WsOut> WsHandler::handle(std::string_view text, WsConnection& conn, bool binary) const {
  std::vector<WsOut> out;
  const WsEmit emit = [&out](WsOut o) { out.push_back(std::move(o)); };
  if (const Work work = receive(text, binary, conn, emit)) work(emit);
  return out;
}

void WsHandler::stream(json begin, protocol::FrameKind kind, const json& id, std::shared_ptr<const void> keep,
                       std::string_view payload, const std::string& end_type, const WsEmit& emit) const {
  auto frames = protocol::split_into_frames(payload, kind, std::uint32_t(id.get<std::uint64_t>()), config_.chunk_bytes);
  begin["request_id"] = id;
  begin["bytes"] = payload.size();
  begin["chunks"] = frames.size();
  emit(WsOut::text(begin));
  for (auto& f : frames) emit({std::move(f.header), keep, f.chunk, true});
  emit(WsOut::text({{"type", end_type}, {"request_id", id}}));
}

// get_mesh: mesh_begin, the Draco bytes in frames of kind 1, mesh_end; with
// lod "preview" or "progressive" first (or only) the preview of a big mesh.
void WsHandler::get_mesh(const json& msg, const json& id, const Caller& caller, const WsEmit& emit) const {
  auto error = [&](const std::string& detail) { emit(WsOut::text(error_message(id, "bad_request", detail))); };
  if (id.is_null()) return error("get_mesh needs a request_id");
  const auto mesh_id = string_field(msg, "mesh_id");
  if (!mesh_id) return error("get_mesh needs a \"mesh_id\" string");
  int bits = 14;
  if (msg.contains("quantization")) {
    if (!msg["quantization"].is_number_integer()) return error("quantization must be an integer 1..30");
    bits = msg["quantization"];
  }
  const auto rec = meshes_.store().get_mesh(*mesh_id, caller);
  if (!rec) return emit(WsOut::text(error_message(id, "not_found", "no mesh with id '" + *mesh_id + "'")));
  // API.md, "Big meshes": "full" is one reply, "preview" the preview of a big
  // mesh (else the mesh), "progressive" the preview and then the mesh.
  const json lod_value = msg.value("lod", json("full"));
  const std::string lod = lod_value.is_string() ? lod_value.get<std::string>() : lod_value.dump();
  if (lod != "full" && lod != "preview" && lod != "progressive")
    return error("lod must be \"full\", \"preview\" or \"progressive\", got " + lod_value.dump());
  check_quantization_bits(bits);  // before a preview is streamed
  auto send = [&](const std::shared_ptr<const EncodedMesh>& enc, const char* level) {
    stream({{"type", "mesh_begin"},
            {"mesh_id", rec->id},
            {"encoding", "draco"},
            {"level", level},
            {"vertices", enc->vertices},
            {"faces", enc->faces},
            {"has_normals", enc->has_normals},
            {"has_colors", enc->has_colors}},
           protocol::FrameKind::draco_mesh, id, enc, enc->bytes, "mesh_end", emit);
  };
  const bool preview = lod != "full" && meshes_.has_preview(*rec);
  if (preview) send(meshes_.preview(*rec), "preview");
  if (!preview || lod == "progressive") {
    send(meshes_.draco(*rec, bits), "full");
    // The viewer asks for the stored order to colour a field or to select:
    // made now, after the stream is queued, it is ready by then.
    try {
      meshes_.stored_order(*rec, bits);
    } catch (const std::exception&) {
      // Asked for again then, and its error answered there.
    }
  }
}

// get_animation: a job's animation artifact (chaos_animate's frames) as
// quantized deltas, zlib-compressed, in frames of kind 3 (protocol/animation_frames.h).
void WsHandler::get_animation(const json& msg, const json& id, const Caller& caller, const WsEmit& emit) const {
  auto error = [&](const std::string& code, const std::string& detail) {
    emit(WsOut::text(error_message(id, code, detail)));
  };
  if (id.is_null()) return error("bad_request", "get_animation needs a request_id");
  const auto job_id = string_field(msg, "job_id");
  if (!job_id) return error("bad_request", "get_animation needs a \"job_id\" string");
  if (!artifacts_.read) return error("not_found", "this server runs no jobs");
  const std::string artifact = string_field(msg, "artifact").value_or("frames");
  std::string raw;
  try {
    raw = artifacts_.read(*job_id, artifact, "frames", caller).bytes;
  } catch (const std::out_of_range& e) {
    return error("not_found", e.what());
  } catch (const UnsupportedFormat&) {
    return error("bad_request", "artifact '" + artifact + "' of job " + *job_id + " is not an animation");
  }
  auto payload = std::make_shared<const std::string>(protocol::encode_animation_payload(raw));
  stream({{"type", "animation_begin"},
          {"job_id", *job_id},
          {"artifact", artifact},
          {"encoding", "frames-delta-zlib"},
          {"raw_bytes", raw.size()}},
         protocol::FrameKind::animation, id, payload, *payload, "animation_end", emit);
}

// get_slice: a 2D slice of a job's voxel grid artifact, zlib-compressed in
// frames of kind 2 (protocol/voxel_slice.h).
void WsHandler::get_slice(const json& msg, const json& id, const Caller& caller, const WsEmit& emit) const {
  auto error = [&](const std::string& code, const std::string& detail) {
    emit(WsOut::text(error_message(id, code, detail)));
  };
  if (id.is_null()) return error("bad_request", "get_slice needs a request_id");
  const auto job_id = string_field(msg, "job_id");
  if (!job_id) return error("bad_request", "get_slice needs a \"job_id\" string");
  const std::string artifact = string_field(msg, "artifact").value_or("grid");
  int axis = -1;
  if (const auto a = string_field(msg, "axis")) axis = *a == "x" ? 0 : *a == "y" ? 1 : *a == "z" ? 2 : -1;
  else if (msg.contains("axis") && msg["axis"].is_number_integer()) axis = msg["axis"].get<int>();
  if (axis < 0 || axis > 2)
    return error("bad_request", "get_slice needs an \"axis\": \"x\", \"y\" or \"z\" (or 0, 1, 2)");
  if (!msg.contains("index") || !msg["index"].is_number_integer())
    return error("bad_request", "get_slice needs an integer \"index\"");
  const long long index = msg["index"].get<long long>();
  if (!artifacts_.read) return error("not_found", "this server runs no jobs");
  std::shared_ptr<const VoxelGrid> kept;
  try {
    kept = grid(*job_id, artifact, caller);
  } catch (const std::out_of_range& e) {
    return error("not_found", e.what());
  } catch (const UnsupportedFormat&) {
    return error("bad_request", "artifact '" + artifact + "' of job " + *job_id + " is not a voxel grid");
  }
  const VoxelGrid& grid = *kept;
  if (index < INT_MIN || index > INT_MAX)
    return error("bad_request", "slice index " + std::to_string(index) + " is out of range");
  const VoxelSlice sl = cgview::slice(grid, axis, int(index));  // InvalidInput out of range: bad_request
  auto payload = std::make_shared<const std::string>(protocol::encode_slice_payload(grid, sl));
  const auto d = grid.dims();
  stream({{"type", "slice"},
          {"job_id", *job_id},
          {"artifact", artifact},
          {"axis", std::string(1, "xyz"[axis])},
          {"index", index},
          {"width", sl.width},
          {"height", sl.height},
          {"dims", {d[0], d[1], d[2]}},
          {"voxel_size", grid.voxel_size()},
          {"origin", {grid.origin().x, grid.origin().y, grid.origin().z}},
          {"encoding", "zlib"}},
         protocol::FrameKind::voxel_slice, id, payload, *payload, "slice_end", emit);
}

std::shared_ptr<const VoxelGrid> WsHandler::grid(const std::string& job, const std::string& name,
                                                 const Caller& caller) const {
  const std::string key = job + "/" + name;
  std::shared_ptr<const VoxelGrid> kept;
  if (artifacts_.check_readable) {  // without it, nothing kept may serve another caller
    std::lock_guard lock(grids_mutex_);
    for (auto it = grids_.begin(); it != grids_.end(); ++it)
      if (it->first == key) {
        kept = it->second;
        grids_.splice(grids_.begin(), grids_, it);
        break;
      }
  }
  if (kept) {
    artifacts_.check_readable(job, caller);  // kept from a request of someone else, maybe
    return kept;
  }
  auto decoded = std::make_shared<const VoxelGrid>(decode_nrrd(artifacts_.read(job, name, "nrrd", caller).bytes, name));
  std::lock_guard lock(grids_mutex_);
  std::erase_if(grids_, [&](const auto& g) { return g.first == key; });
  grids_.emplace_front(key, decoded);
  while (grids_.size() > config_.kept_grids) grids_.pop_back();
  return decoded;
}

}  // namespace cgview::server
