// Starting a helper program as a child of the server (a job's worker, an
// upload's reader), the one place that knows how a child of a threaded,
// signal-handling server is made: signals blocked across the fork, an
// address-space limit, no core file, its own process group, killed with the
// server, and no descriptor of the server's but stdin, stdout and stderr.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cgview::server {

struct ChildOptions {
  std::size_t memory_mb = 0;          // RLIMIT_AS; 0: none
  int stdin_fd = -1;                  // the child's stdin (closed in the parent by the caller); -1: /dev/null
  int stdout_fd = -1;                 // the child's stdout (closed in the parent by the caller); -1: /dev/null
  std::filesystem::path stderr_file;  // the child's stderr, truncated; empty: /dev/null
  int stderr_fd = -1;                 // else this descriptor (a pipe; closed in the parent by the caller)
  bool stderr_to_stdout = false;      // stderr goes where stdout goes (stderr_file unused)
  // A sandboxed child (sandbox.h): its processes (RLIMIT_NPROC, counted per
  // user; 0: none) and the largest file it may write (RLIMIT_FSIZE; 0: none).
  int processes = 0;
  std::size_t file_mb = 0;
  // A child that must end with the server (a job's worker, an upload's
  // reader, through the sandbox): it gets the read end of a pipe whose
  // write end only the server holds, as fd 3 named by CGVIEW_SERVER_FD, and
  // watches it (end_with_server), instead of the parent-death signal.  That
  // signal, sent to bubblewrap while it sets a sandbox up, leaves the
  // sandbox's first process waiting forever for a parent that is gone;
  // left alone, bubblewrap finishes, starts the child, and the child ends.
  bool end_with_server = false;
  // The child's environment is a short list the server writes (clean_env),
  // not the server's own: PATH, the locale, HOME and TMPDIR as /tmp, and
  // the variables that choose a GPU, the renderer and the plugins'
  // compiler (job_environment() lists them).  A job never reads the
  // server's secrets, its configuration or its command line from there.
  bool clean_env = false;
  // The mount namespace the child enters just before its exec (an open
  // /proc/PID/ns/mnt); -1: the server's.  A root server's bubblewraps
  // start in one with fewer mounts (Sandbox), each of which bubblewrap
  // would read again after every mount it makes.
  int mount_ns_fd = -1;
  // A descriptor the child gets as kChildDataFd, to read: bubblewrap copies
  // a sandboxed job's job.json from it into the sandbox's own memory
  // (--ro-bind-data), so that no file of it is made on the server's disk.
  // -1: none.
  int data_fd = -1;
};

// The number the child holds ChildOptions::data_fd at (after the server's
// life pipe, 3).
inline constexpr int kChildDataFd = 4;

// The server's variables a job gets ("NAME=value"): the locale, PATH and
// those that choose a GPU, the renderer and the plugins' compiler.  A clean
// child gets them, and HOME and TMPDIR as /tmp.
std::vector<std::string> job_environment();

// The child's side of ChildOptions::end_with_server: where CGVIEW_SERVER_FD
// names such a pipe, a thread waits on it and, when it reads anything but
// data (the server is gone, or the descriptor was closed under it), kills
// the child's process group: the child and what it started.  Nothing where
// the variable is not set (a worker run by hand, or by Slurm).
void end_with_server();

// Forks and execs argv[0] (a path) with argv; the child's pid, or -1 when
// fork fails.  A child that cannot exec exits with status 127.
pid_t spawn_child(const std::vector<std::string>& argv, const ChildOptions& options);

// Sends `sig` to the child and to its process group: what it started there
// goes with it (bubblewrap killed while it sets a sandbox up leaves the
// sandbox's first process in that group, waiting for it forever).  The
// group is the child's as long as the child is not reaped.
void kill_child(pid_t pid, int sig);

// Waits for the child to exit, at most `limit`; its wait status, or nullopt
// when the time ran out (the child, and its process group, are then killed
// with SIGKILL and reaped).
std::optional<int> wait_child(pid_t pid, std::chrono::milliseconds limit);

// Runs a command-line tool (argv[0] a path) to its end, at most `limit`:
// its wait status (nullopt when it ran out of time and was killed) and what
// it printed, stdout and stderr together.
struct ToolRun {
  std::optional<int> status;
  std::string output;
  bool ok() const;  // exited with 0
};
ToolRun run_tool(const std::vector<std::string>& argv, std::chrono::milliseconds limit);

// The full path of a program found on PATH, or "" (`name` with a '/' is taken as it is).
std::filesystem::path find_program(const std::string& name);

// "SIGSEGV", "SIGKILL", ... or "signal N".
std::string signal_name(int sig);

}  // namespace cgview::server
