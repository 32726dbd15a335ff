// The real cgview-server started on a free port for a benchmark, and a mesh
// upload to it; shared by ws_bench and jobs_bench.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include <sys/types.h>

namespace cgview::bench {

// cgview-server --port 0 --data-dir DATA --samples none EXTRA..., its port
// read from the first line it prints; SIGTERM and waited for on destruction.
// Throws when the server does not start.
struct ServerProcess {
  pid_t pid = -1;
  unsigned short port = 0;
  ServerProcess(const std::string& exe, const std::filesystem::path& data, const std::vector<std::string>& extra = {});
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;
  // Peak resident memory in kB (VmHWM), or -1.
  long peak_rss_kb() const;
};

// One request on its own connection (with "Authorization: Bearer TOKEN"
// when a token is given): the status and the body.
std::pair<int, std::string> call(unsigned short port, const std::string& method, const std::string& target,
                                 const std::string& body = "", const std::string& token = "");
// POST /api/v1/meshes?name=NAME on its own connection; the new mesh's id.
// Throws "upload failed: BODY" unless the answer is 201.
std::string upload(unsigned short port, const std::string& name, const std::string& bytes,
                   const std::string& token = "");

// A JSON request with a token (null body: none); its JSON answer.  Throws
// "METHOD TARGET: STATUS BODY" for an answer of 300 or more.
nlohmann::json request(unsigned short port, const std::string& method, const std::string& target,
                       const nlohmann::json& body, const std::string& token);
// `cgview-server --data-dir DATA user add tina --role teacher`, before the
// server starts: the teacher's token.
std::string add_teacher(const std::string& exe, const std::filesystem::path& data);
// The q-quantile of v (0..1, nearest rank); 0 for none.
double percentile(std::vector<double> v, double q);

}  // namespace cgview::bench
