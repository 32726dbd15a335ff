// The sandbox every job's worker (and every plugin build, which runs as a
// job) starts in: Debian's bubblewrap, with no network, a read-only view of
// the system, the server's data directory hidden, only the job's own
// directory writable, its own process, IPC and user namespaces, and limits
// on processes and on the size of a file, beside the time and memory limits
// the executor already sets.  A server running as root runs each worker as
// a user of its own (root is exempt from the process limit, and the job's
// files are then the only ones that user has).
//
// Where bubblewrap cannot start (no user namespaces, not installed), the
// server says so at start; workers then run as before, and plugins (code
// from users) are refused unless the admin allows them knowingly.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "child_process.h"

namespace cgview::server {

struct SandboxConfig {
  std::string mode = "auto";       // "auto": bubblewrap where it works; "required": refuse to start without; "off"
  int processes = 256;             // processes and threads of one job
  std::size_t file_mb = 4096;      // the largest file a job writes
  long uid_base = 2'000'000'000L;  // a root server's workers run as uid_base + slot (bwrap maps ids below 2^31)
  std::vector<std::filesystem::path> hidden;  // more paths a job must not see (the config file's secrets)
  // Directories a job reads at their own paths even where they lie under
  // /tmp (the job's /tmp is its own): the plugins' headers and compiler
  // cache of a build tree, set by the server.
  std::vector<std::filesystem::path> visible;
};

// Where a sandboxed job sees its directory, its inputs and its plugin: its
// own paths, since a root server's job user may not walk the data
// directory's (a 0700 directory above it, as mktemp makes).
// (Under /run, an empty tmpfs in the sandbox: the system's sockets there,
// munge's among them, are not the job's.)
inline constexpr const char* kSandboxJob = "/run/cgview/job";
inline constexpr const char* kSandboxSpec = "/run/cgview/job.json";  // its job.json, read-only
inline constexpr const char* kSandboxInputs = "/run/cgview/in";
inline constexpr const char* kSandboxPlugin = "/run/cgview/plugin";
inline constexpr const char* kSandboxPrograms = "/run/cgview/bin";

// What one sandboxed run sees besides the read-only system.
struct SandboxMounts {
  std::filesystem::path writable;  // the job's directory (given to the job's user), seen at kSandboxJob;
                                   // and at /tmp too (the job's /tmp is its directory)
  std::vector<std::pair<std::filesystem::path, std::string>> readable;  // a file -> where the job sees it, read-only
  std::vector<std::filesystem::path> hidden;  // replaced by an empty read-only directory (the data directory)
  std::vector<std::filesystem::path>
      visible;  // read-only at their own paths, over the job's /tmp too (the worker's directory)
  // A descriptor's bytes as a read-only file the job sees at `data_at` (its
  // job.json): bubblewrap copies them into the sandbox's own memory, so no
  // file is made for them on the server's disk.  -1: none.
  int data_fd = -1;
  std::string data_at = {};
};

// The variable that tells a program that drops to the job's user itself
// (Sandbox::Drop::by_program) that user's id.
inline constexpr const char* kJobUserVariable = "CGVIEW_JOB_USER";

// In a root sandbox's program given kJobUserVariable, before anything of
// the job runs: what setpriv would have done (no new privileges, an empty
// bounding set, no groups, the user `id` as real, effective and saved user
// and group, no capabilities left), then checked in /proc/self/status.
// Throws IoError where any of it fails, or where the process has more than
// one thread (the rest would keep their privileges).
void drop_to_job_user(long id);

class Sandbox {
 public:
  // Probes bubblewrap once (a run of /bin/true in a full sandbox).
  Sandbox(SandboxConfig config, std::filesystem::path bwrap = {});
  ~Sandbox();
  Sandbox(const Sandbox&) = delete;
  Sandbox& operator=(const Sandbox&) = delete;
  bool enabled() const { return enabled_; }
  // Why it is off ("bwrap is not installed", its own error), for the start message.
  const std::string& why_not() const { return why_not_; }
  const SandboxConfig& config() const { return config_; }

  // The command to run `argv` sandboxed, and the child options that go with
  // it (its limits; memory_mb and stdout are the caller's).  `slot` picks
  // the user of a root server's run (one per run at a time), who is given
  // the job's directory.  Throws IoError when it cannot be.  Unchanged argv
  // where the sandbox is off.
  struct Command {
    std::vector<std::string> argv;
    ChildOptions options;
  };
  // Who drops a root server's run to its user: setpriv, exec'd before the
  // program, or the program itself (cgview-worker), told the user in its
  // environment (kJobUserVariable), which saves an exec for each job.  (A
  // wrapper script given as the worker then runs as root in the sandbox,
  // with no capability but those the drop takes and the one to reach the
  // job's files, until the worker it starts drops.)
  enum class Drop { by_setpriv, by_program };
  Command wrap(const std::vector<std::string>& argv, const SandboxMounts& mounts, int slot, ChildOptions options = {},
               Drop drop = Drop::by_setpriv) const;

  // Whether a sandboxed run sees the existing `path` at its own path, through
  // the read-only root, and may walk to it as the job's user: not under
  // what the sandbox replaces (its /tmp, /run, /dev, /proc), and every
  // directory above it, and it, open to all (o+x).  Such a path needs no
  // mount of its own.  Remembered once found (the worker's directory, the
  // plugins' headers: asked for every job).
  bool shows_at_own_path(const std::filesystem::path& path) const;

  // The user a root server's run in `slot` runs as; nullopt where runs keep
  // the server's user (a server that is not root, or no sandbox).
  std::optional<long> job_user(int slot) const;

  // A slot no other run (a job's worker, an upload's reader) holds while
  // this one lives: the lowest free, given back when it is destroyed.
  class Slot {
   public:
    Slot() = default;
    Slot(Slot&& o) noexcept : held_(std::move(o.held_)), number_(o.number_) {}
    Slot& operator=(Slot&& o) noexcept;
    ~Slot() { give_back(); }
    int number() const { return number_; }

   private:
    friend class Sandbox;
    struct Held {
      std::mutex mutex;
      std::set<int> numbers;
    };
    void give_back();
    std::shared_ptr<Held> held_;
    int number_ = -1;
  };
  Slot take_slot() const;

 private:
  SandboxConfig config_;
  std::filesystem::path bwrap_, setpriv_;
  // A server that is not root limits a job's processes from inside its
  // user namespace (prlimit, util-linux), where the kernel counts that
  // job's processes alone: a limit set before bubblewrap counts every
  // process of the server's user, so one job's could starve another's.
  std::filesystem::path prlimit_;
  // A root server's bubblewraps start in a mount namespace of its own
  // making, the system's without the mounts no job uses (the control
  // groups, terminals, message queues and other kernel file systems below
  // /proc, /sys and /dev): bubblewrap reads the whole mount table again
  // after each of a job's ~20 mounts, twice over (the old root and the new),
  // and those reads were 40% of its CPU.  Its descriptor, which keeps it;
  // -1: none (the server's namespace).
  int mount_ns_ = -1;
  // Whether that namespace's /dev is the jobs' own, made once (read-only,
  // the devices bubblewrap's --dev gives), which each run binds whole
  // rather than have bubblewrap make one (sandbox.cpp, jobs_dev_nodes).
  bool jobs_dev_ = false;
  // Of shows_at_own_path: for each path asked, its real path's place
  // (under what the sandbox replaces) and whether all may walk to it.
  struct Place {
    bool replaced = false, open_to_all = false;
  };
  std::optional<Place> place(const std::filesystem::path& path) const;  // nullopt: it does not exist
  mutable std::mutex places_mutex_;
  mutable std::map<std::filesystem::path, Place> places_;
  bool enabled_ = false;
  std::string why_not_;
  std::shared_ptr<Slot::Held> slots_ = std::make_shared<Slot::Held>();
};

}  // namespace cgview::server
