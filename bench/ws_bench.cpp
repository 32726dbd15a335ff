// The server's mesh streaming: Draco encoding of a 1M-triangle mesh, bytes on
// the wire against the raw float32/uint32 buffers and against gzip of them,
// and 50 WebSocket clients fetching the same mesh at once (total time, the
// server's peak memory).  Starts the real cgview-server on a free port.
//
//   build/bin/ws_bench [--clients 50] [--server build/bin/cgview-server] [--save-mesh FILE.ply]
#include <utility>  // before Boost 1.74's asio (std::exchange)

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <zlib.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include "bench_server.h"
#include "frames.h"
#include "io/mesh_io.h"
#include "io/samples.h"

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using nlohmann::json;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using cgview::bench::ServerProcess;
using cgview::bench::upload;

namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Fetches a mesh over a WebSocket; returns the reassembled payload size.
std::size_t fetch(unsigned short port, const std::string& id, double* seconds) {
  net::io_context ioc;
  websocket::stream<beast::tcp_stream> ws(ioc);
  ws.read_message_max(64 << 20);
  const auto t0 = Clock::now();
  beast::get_lowest_layer(ws).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  ws.handshake("127.0.0.1", "/api/v1/ws");
  ws.write(net::buffer(json{{"type", "get_mesh"}, {"request_id", 1}, {"mesh_id", id}}.dump()));
  std::string payload;
  for (;;) {
    beast::flat_buffer b;
    ws.read(b);
    const std::string msg = beast::buffers_to_string(b.data());
    if (ws.got_binary()) {
      std::string_view chunk;
      cgview::protocol::decode_frame(msg, &chunk);
      payload.append(chunk);
      continue;
    }
    const json j = json::parse(msg);
    if (j["type"] == "mesh_end") break;
    if (j["type"] == "error") throw std::runtime_error(j.dump());
  }
  if (seconds) *seconds = seconds_since(t0);
  ws.close(websocket::close_code::normal);
  return payload.size();
}

std::size_t gzip_size(const std::string& raw) {
  uLongf n = compressBound(uLong(raw.size()));
  std::string out(n, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()),
                6) != Z_OK)
    throw std::runtime_error("zlib failed");
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  int clients = 50;
  std::string exe = (fs::path(argv[0]).parent_path() / "cgview-server").string();
  std::string save;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--clients" && i + 1 < argc) clients = std::max(0, std::atoi(argv[++i]));
    else if (a == "--server" && i + 1 < argc) exe = argv[++i];
    else if (a == "--save-mesh" && i + 1 < argc) save = argv[++i];
    else {
      std::fprintf(stderr, "usage: ws_bench [--clients N] [--server PATH] [--save-mesh FILE.ply]\n");
      return 2;
    }
  }
  using namespace cgview;
  const auto base = resolve_mesh_path("bunny00.off");
  if (!base) {
    std::fprintf(stderr, "ws_bench: sample meshes not found\n");
    return 1;
  }
  const Mesh mesh = subdivide_midpoint(subdivide_midpoint(read_mesh(*base)));
  const std::string ply = write_mesh_bytes(mesh, MeshFormat::ply);
  if (!save.empty()) {
    std::ofstream(save, std::ios::binary) << ply;  // the same mesh, for bench/browser_bench.mjs
  }
  if (clients == 0) return 0;  // --clients 0: only save the mesh

  // Raw buffers as a viewer would receive them: float32 positions, uint32 indices.
  std::string raw;
  raw.reserve(mesh.num_vertices() * 12 + mesh.num_faces() * 12);
  for (const Vec3& p : mesh.positions) {
    const float xyz[3] = {float(p.x), float(p.y), float(p.z)};
    raw.append(reinterpret_cast<const char*>(xyz), 12);
  }
  raw.append(reinterpret_cast<const char*>(mesh.faces.data()), mesh.faces.size() * 12);
  auto t = Clock::now();
  const std::size_t gz = gzip_size(raw);
  const double gzip_s = seconds_since(t);

  const fs::path data = fs::temp_directory_path() / ("cgview-ws-bench-" + std::to_string(getpid()));
  fs::remove_all(data);
  int rc = 0;
  {
    ServerProcess server(exe, data);
    const std::string id = upload(server.port, "bunny_1m.ply", ply);
    const long rss_before = server.peak_rss_kb();
    double first = 0, second = 0;
    const std::size_t wire = fetch(server.port, id, &first);  // encodes
    fetch(server.port, id, &second);                          // from the cache

    std::printf("## Draco over WebSocket: %zu vertices, %zu triangles (bunny00 subdivided twice)\n\n",
                mesh.num_vertices(), mesh.num_faces());
    std::printf("| measure | value |\n|---|---:|\n");
    std::printf("| raw float32 positions + uint32 indices | %.2f MB |\n", raw.size() / 1e6);
    std::printf("| gzip -6 of the raw buffers | %.2f MB (%.1f%% of raw, %.2f s to compress) |\n", gz / 1e6,
                100.0 * gz / raw.size(), gzip_s);
    std::printf("| Draco, 14-bit positions (bytes on the wire) | %.2f MB (%.1f%% of raw) |\n", wire / 1e6,
                100.0 * wire / raw.size());
    std::printf("| first fetch: encode + send, one client | %.3f s |\n", first);
    std::printf("| second fetch: from the cache | %.3f s |\n", second);

    std::vector<std::thread> threads;
    std::vector<double> times(std::size_t(clients), 0);
    std::vector<std::size_t> sizes(std::size_t(clients), 0);
    t = Clock::now();
    for (int c = 0; c < clients; ++c)
      threads.emplace_back([&, c] {
        try {
          sizes[std::size_t(c)] = fetch(server.port, id, &times[std::size_t(c)]);
        } catch (const std::exception& e) {
          std::fprintf(stderr, "client %d: %s\n", c, e.what());
        }
      });
    for (auto& th : threads) th.join();
    const double total = seconds_since(t);
    int ok = 0;
    for (std::size_t s : sizes) ok += s == wire;
    std::sort(times.begin(), times.end());
    std::printf(
        "| %d concurrent clients, same mesh: total | %.3f s (%d of %d complete; slowest %.3f s, median %.3f s) |\n",
        clients, total, ok, clients, times.back(), times[times.size() / 2]);
    std::printf("| server peak memory (VmHWM) | %.0f MB (%.0f MB before the fetches) |\n",
                server.peak_rss_kb() / 1024.0, rss_before / 1024.0);
    if (ok != clients) rc = 1;
    // The same ratio on a sample mesh with real detail, encoded in-process.
    if (const auto man = resolve_mesh_path("man.off")) {
      const Mesh m = read_mesh(*man);
      const std::size_t man_raw = m.num_vertices() * 12 + m.num_faces() * 12;
      const auto t1 = Clock::now();
      const std::size_t man_drc = write_mesh_bytes(m, MeshFormat::drc).size();
      std::printf(
          "| CGAL's man.off (%zu triangles): Draco 14-bit | %.1f KB (%.1f%% of %.1f KB raw; encoded in %.3f s) |\n",
          m.num_faces(), man_drc / 1e3, 100.0 * man_drc / man_raw, man_raw / 1e3, seconds_since(t1));
    }
  }
  fs::remove_all(data);
  return rc;
}
