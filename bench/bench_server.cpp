#include "bench_server.h"

#include <utility>  // before Boost 1.74's asio (std::exchange)

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace cgview::bench {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;
using nlohmann::json;

ServerProcess::ServerProcess(const std::string& exe, const std::filesystem::path& data,
                             const std::vector<std::string>& extra) {
  std::vector<std::string> args = {exe, "--port", "0", "--data-dir", data.string(), "--samples", "none"};
  args.insert(args.end(), extra.begin(), extra.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int out[2];
  if (pipe(out) != 0) throw std::runtime_error("pipe");
  pid = fork();
  if (pid == 0) {
    dup2(out[1], 1);
    close(out[0]);
    execv(exe.c_str(), argv.data());
    _exit(127);
  }
  close(out[1]);
  std::string line;
  char c;
  while (read(out[0], &c, 1) == 1 && c != '\n') line += c;
  close(out[0]);
  const auto colon = line.find(':', line.find("127.0.0.1"));
  if (colon == std::string::npos) throw std::runtime_error("the server did not start: " + line);
  port = static_cast<unsigned short>(std::stoi(line.substr(colon + 1)));
}

ServerProcess::~ServerProcess() {
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
}

long ServerProcess::peak_rss_kb() const {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  std::string k;
  long v = 0;
  while (f >> k)
    if (k == "VmHWM:") {
      f >> v;
      return v;
    }
  return -1;
}

std::pair<int, std::string> call(unsigned short port, const std::string& method, const std::string& target,
                                 const std::string& body, const std::string& token) {
  net::io_context ioc;
  beast::tcp_stream s(ioc);
  s.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> req(http::string_to_verb(method), target, 11);
  req.set(http::field::host, "127.0.0.1");
  if (!token.empty()) req.set(http::field::authorization, "Bearer " + token);
  req.body() = body;
  req.prepare_payload();
  http::write(s, req);
  beast::flat_buffer buf;
  http::response_parser<http::string_body> p;
  p.body_limit(1 << 30);
  http::read(s, buf, p);
  return {p.get().result_int(), p.get().body()};
}

std::string upload(unsigned short port, const std::string& name, const std::string& bytes, const std::string& token) {
  const auto [status, body] = call(port, "POST", "/api/v1/meshes?name=" + name, bytes, token);
  if (status != 201) throw std::runtime_error("upload failed: " + body);
  return json::parse(body)["id"];
}

json request(unsigned short port, const std::string& method, const std::string& target, const json& body,
             const std::string& token) {
  const auto [status, text] = call(port, method, target, body.is_null() ? "" : body.dump(), token);
  if (status >= 300) throw std::runtime_error(method + " " + target + ": " + std::to_string(status) + " " + text);
  return json::parse(text);
}

std::string add_teacher(const std::string& exe, const std::filesystem::path& data) {
  const std::string cmd = exe + " --data-dir " + data.string() + " user add tina --role teacher 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  char buf[256] = {};
  const bool read = p && std::fgets(buf, sizeof buf, p);
  if (p) pclose(p);
  std::string t = read ? buf : "";
  while (!t.empty() && (t.back() == '\n' || t.back() == '\r')) t.pop_back();
  if (t.empty()) throw std::runtime_error("cannot add the teacher");
  return t;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

}  // namespace cgview::bench
