#include "slurm_cluster.h"

#include <dirent.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <pwd.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <thread>

extern char** environ;

namespace fs = std::filesystem;

namespace cgview::test {
namespace {

using Clock = std::chrono::steady_clock;

void sleep_s(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// slurmctld and slurmd are in /usr/sbin, which a normal user's PATH may lack.
std::string find_program(const std::string& name) {
  std::vector<std::string> dirs;
  if (const char* path = std::getenv("PATH")) {
    std::stringstream ss(path);
    for (std::string d; std::getline(ss, d, ':');)
      if (!d.empty()) dirs.push_back(d);
  }
  for (const char* d : {"/usr/sbin", "/sbin", "/usr/local/sbin", "/usr/bin", "/usr/local/bin"}) dirs.push_back(d);
  for (const auto& d : dirs) {
    const std::string p = d + "/" + name;
    if (::access(p.c_str(), X_OK) == 0) return p;
  }
  return {};
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  std::size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
}

std::string user_name() {
  if (const passwd* pw = ::getpwuid(::geteuid())) return pw->pw_name;
  return std::to_string(::geteuid());
}

// A port that nothing listens on now, below Linux's ephemeral range
// (32768-60999), so that the outgoing connections of tests running beside
// this one do not take it between this check and the daemon's bind.
bool port_free(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_ANY);
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  const bool ok = ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  ::close(fd);
  return ok;
}

std::vector<int> free_ports(int n) {
  std::mt19937 rng(std::random_device{}());
  std::uniform_int_distribution<int> pick(20000, 32000);
  std::vector<int> ports;
  for (int tries = 0; static_cast<int>(ports.size()) < n && tries < 10000; ++tries) {
    const int p = pick(rng);
    bool taken = false;
    for (int q : ports) taken = taken || q == p;
    if (!taken && port_free(p)) ports.push_back(p);
  }
  return ports;
}

std::string read_tail(const fs::path& p, int lines) {
  std::ifstream f(p, std::ios::binary);
  if (!f) return {};
  std::vector<std::string> all;
  for (std::string l; std::getline(f, l);) all.push_back(l);
  std::string out;
  for (std::size_t i = all.size() > static_cast<std::size_t>(lines) ? all.size() - lines : 0; i < all.size(); ++i)
    out += all[i] + "\n";
  return out;
}

std::vector<pid_t> all_pids() {
  std::vector<pid_t> pids;
  DIR* d = ::opendir("/proc");
  if (!d) return pids;
  while (dirent* e = ::readdir(d)) {
    char* end = nullptr;
    const long v = std::strtol(e->d_name, &end, 10);
    if (end && *end == '\0' && v > 0) pids.push_back(static_cast<pid_t>(v));
  }
  ::closedir(d);
  return pids;
}

// Whether the process holds one of `paths` open (a process we may not
// inspect holds none, as far as we can tell, and we could not kill it either).
bool holds_open(pid_t pid, const std::set<std::string>& paths) {
  std::error_code ec;
  const fs::path fds = fs::path("/proc") / std::to_string(pid) / "fd";
  for (fs::directory_iterator it(fds, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code lec;
    const fs::path target = fs::read_symlink(it->path(), lec);
    if (!lec && paths.count(target.string())) return true;
  }
  return false;
}

// Whether the process is one of this cluster's jobs: Slurm puts SLURM_JOB_ID,
// SLURM_CLUSTER_NAME and the cluster's SLURM_CONF into every job's
// environment, --export=NONE included.  (A program under test that was given
// SLURM_CONF, inside a CI job of a real Slurm, has another cluster's name.)
bool is_job_of(pid_t pid, const std::string& conf_entry, const std::string& cluster_entry) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/environ", std::ios::binary);
  bool conf = false, cluster = false, job = false;
  for (std::string e; std::getline(f, e, '\0');) {
    conf = conf || e == conf_entry;
    cluster = cluster || e == cluster_entry;
    job = job || e.rfind("SLURM_JOB_ID=", 0) == 0;
  }
  return conf && cluster && job;
}

bool is_ended(const std::string& state) {
  static const std::set<std::string> ended = {"COMPLETED", "FAILED",    "CANCELLED", "TIMEOUT",   "OUT_OF_MEMORY",
                                              "NODE_FAIL", "BOOT_FAIL", "DEADLINE",  "PREEMPTED", "REVOKED"};
  return ended.count(state) > 0;
}

}  // namespace

SlurmCluster::~SlurmCluster() { stop(); }

bool SlurmCluster::available(std::string* why) {
  std::string missing;
  for (const char* p :
       {"munged", "slurmctld", "slurmd", "slurmstepd", "sbatch", "squeue", "sinfo", "scancel", "scontrol", "sacct"})
    if (find_program(p).empty()) missing += std::string(missing.empty() ? "" : ", ") + p;
  if (missing.empty()) return true;
  if (why) *why = "not installed: " + missing + " (Debian: munge, slurm-wlm; ./setup.sh installs them)";
  return false;
}

void SlurmCluster::set_conf(const std::string& key, const std::string& value) {
  for (auto& [k, v] : conf_)
    if (k == key) {
      v = value;
      return;
    }
  conf_.emplace_back(key, value);
}

std::vector<std::pair<std::string, std::string>> SlurmCluster::effective_conf() const {
  const std::string d = dir_.string();
  const std::string user = user_name();
  // Defaults first; set_conf() replaces a key in place or adds one at the end.
  std::vector<std::pair<std::string, std::string>> c = {
      {"ClusterName", "cgview"},
      {"SlurmctldHost", "localhost(127.0.0.1)"},
      {"SlurmctldPort", std::to_string(ctld_port_)},
      {"SlurmdPort", std::to_string(node_ports_.empty() ? 0 : node_ports_.front())},  // each NodeName has its own Port=
      {"SlurmUser", user},
      {"SlurmdUser", user},
      {"AuthType", "auth/munge"},
      {"CredType", "cred/munge"},
      {"AuthInfo", "socket=" + d + "/munge/munge.socket"},
      {"StateSaveLocation", d + "/state"},
      {"SlurmdSpoolDir", d + "/spool/%n"},
      {"SlurmctldPidFile", d + "/slurmctld.pid"},
      {"SlurmdPidFile", d + "/slurmd.%n.pid"},
      {"SlurmctldLogFile", d + "/slurmctld.log"},
      {"SlurmdLogFile", d + "/slurmd.%n.log"},
      {"SlurmctldDebug", "info"},
      {"SlurmdDebug", "info"},
      // No cgroups: the process tree is found through /proc, and --mem is
      // enforced by the accounting poller (OverMemoryKill) every second.
      {"ProctrackType", "proctrack/linuxproc"},
      {"TaskPlugin", "task/none"},
      {"MpiDefault", "none"},
      {"SelectType", "select/cons_tres"},
      {"SelectTypeParameters", "CR_Core_Memory"},
      // Without it a job without --mem takes the whole node's RealMemory, so
      // that only one job runs on a node at a time.
      {"DefMemPerCPU", "100"},
      {"JobAcctGatherType", "jobacct_gather/linux"},
      {"JobAcctGatherFrequency", "1"},
      {"JobAcctGatherParams", "OverMemoryKill"},
      {"AccountingStorageType", "accounting_storage/none"},
      {"JobCompType", "jobcomp/filetxt"},
      {"JobCompLoc", d + "/jobcomp.txt"},
      {"SchedulerType", "sched/backfill"},
      {"SchedulerParameters", "batch_sched_delay=0,sched_interval=1"},
      {"ReturnToService", "2"},
      {"SlurmdTimeout", "20"},
      {"MinJobAge", "300"},
      {"KillWait", "2"},
      {"InactiveLimit", "0"},
      {"Waittime", "0"},
  };
  for (const auto& [k, v] : conf_) {
    bool replaced = false;
    for (auto& [ck, cv] : c)
      if (ck == k) {
        cv = v;
        replaced = true;
      }
    if (!replaced) c.emplace_back(k, v);
  }
  return c;
}

std::string SlurmCluster::conf_value(const std::string& key) const {
  for (const auto& [k, v] : effective_conf())
    if (k == key) return v;
  return {};
}

std::string SlurmCluster::conf_text() const {
  std::string text = "# Written by cgview::test::SlurmCluster (tests/slurm/slurm_cluster.cpp).\n";
  for (const auto& [k, v] : effective_conf()) text += k + "=" + v + "\n";
  std::string names;
  for (std::size_t i = 0; i < node_ports_.size(); ++i) {
    const std::string n = node_name(static_cast<int>(i) + 1);
    text += "NodeName=" + n + " NodeHostname=localhost NodeAddr=127.0.0.1 Port=" + std::to_string(node_ports_[i]) +
            " CPUs=2 RealMemory=4000 State=UNKNOWN\n";
    names += (i ? "," : "") + n;
  }
  text += "PartitionName=debug Nodes=" + names + " Default=YES MaxTime=INFINITE State=UP\n";
  return text;
}

bool SlurmCluster::fail(std::string* why, const std::string& message) {
  if (why) *why = message + "\n" + log_tail();
  stop();
  return false;
}

bool SlurmCluster::start(const fs::path& dir, int nodes, std::string* why) {
  if (running()) return fail(why, "SlurmCluster::start: already started");
  if (nodes < 1) return fail(why, "SlurmCluster::start: nodes must be at least 1");
  std::string missing;
  if (!available(&missing)) return fail(why, missing);

  std::error_code ec;
  fs::create_directories(dir, ec);
  // /proc shows the daemons' open files by their canonical paths.
  dir_ = fs::weakly_canonical(dir, ec);
  if (ec) return fail(why, "SlurmCluster::start: " + dir.string() + ": " + ec.message());
  // A fresh cluster: no jobs recovered from an earlier one's state.
  for (const char* old : {"state", "spool", "jobcomp.txt"}) fs::remove_all(dir_ / old, ec);
  for (const char* sub : {"munge", "state", "spool"}) fs::create_directories(dir_ / sub, ec);
  for (int i = 1; i <= nodes; ++i) fs::create_directories(dir_ / "spool" / node_name(i), ec);
  // munged refuses a socket directory that is not searchable by all, or a
  // key in a directory others may write.
  fs::permissions(dir_, fs::perms(0755), ec);
  fs::permissions(dir_ / "munge", fs::perms(0755), ec);

  const std::vector<int> ports = free_ports(nodes + 1);
  if (static_cast<int>(ports.size()) != nodes + 1) return fail(why, "SlurmCluster::start: no free ports");
  ctld_port_ = ports[0];
  node_ports_.assign(ports.begin() + 1, ports.end());

  {
    const fs::path key = dir_ / "munge" / "munge.key";
    fs::remove(key, ec);
    std::array<char, 1024> bytes;
    std::ifstream rnd("/dev/urandom", std::ios::binary);
    if (!rnd.read(bytes.data(), bytes.size())) return fail(why, "SlurmCluster::start: cannot read /dev/urandom");
    std::ofstream k(key, std::ios::binary);
    k.write(bytes.data(), bytes.size());
    k.close();
    fs::permissions(key, fs::perms::owner_read, ec);
    std::ofstream c(conf(), std::ios::binary);
    c << conf_text();
    if (!c) return fail(why, "SlurmCluster::start: cannot write " + conf().string());
  }

  const std::string m = (dir_ / "munge").string();
  munged_ = {"munged",
             {find_program("munged"), "--foreground", "--force", "--key-file=" + m + "/munge.key",
              "--socket=" + m + "/munge.socket", "--pid-file=" + m + "/munged.pid", "--seed-file=" + m + "/munged.seed",
              "--log-file=" + m + "/munged.log", "--num-threads=2"},
             dir_ / "munged.out"};
  if (!spawn(munged_, why)) return fail(why, "SlurmCluster::start: cannot start munged");
  for (const auto t0 = Clock::now(); !fs::exists(dir_ / "munge" / "munge.socket");) {
    if (::waitpid(munged_.pid, nullptr, WNOHANG) == munged_.pid) {
      munged_.pid = 0;
      return fail(why, "SlurmCluster::start: munged exited");
    }
    if (since(t0) > 5) return fail(why, "SlurmCluster::start: munged made no socket in 5 s");
    sleep_s(0.02);
  }

  ctld_ = {"slurmctld", {find_program("slurmctld"), "-D", "-f", conf().string()}, dir_ / "slurmctld.out"};
  if (!spawn(ctld_, why)) return fail(why, "SlurmCluster::start: cannot start slurmctld");
  slurmd_.clear();
  for (int i = 1; i <= nodes; ++i)
    slurmd_.push_back({node_name(i),
                       {find_program("slurmd"), "-D", "-N", node_name(i), "-f", conf().string()},
                       dir_ / ("slurmd." + node_name(i) + ".out")});
  for (auto& d : slurmd_)
    if (!spawn(d, why)) return fail(why, "SlurmCluster::start: cannot start slurmd " + d.name);

  std::string wait_why;
  if (!wait_nodes_idle(20, &wait_why)) return fail(why, wait_why);
  node_start_times_.clear();
  for (int i = 1; i <= nodes; ++i) {
    const std::string out = run("scontrol -o show node " + node_name(i));
    const auto at = out.find("SlurmdStartTime=");
    node_start_times_.push_back(at == std::string::npos ? "" : out.substr(at + 16, out.find(' ', at) - at - 16));
  }
  return true;
}

bool SlurmCluster::spawn(Daemon& d, std::string* why) {
  // Everything the child needs is made before fork(): it runs only
  // async-signal-safe calls until execve.
  std::vector<std::string> env_strings;
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("SLURM_CONF=", 0) != 0) env_strings.emplace_back(*e);
  env_strings.push_back("SLURM_CONF=" + conf().string());
  std::vector<char*> envp, argv;
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  for (auto& s : d.argv) argv.push_back(s.data());
  argv.push_back(nullptr);
  if (d.argv.empty() || d.argv[0].empty()) {
    if (why) *why = d.name + ": program not found";
    return false;
  }
  const int out = ::open(d.out.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  const int null = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (out < 0 || null < 0) {
    if (out >= 0) ::close(out);
    if (null >= 0) ::close(null);
    if (why) *why = d.out.string() + ": " + std::strerror(errno);
    return false;
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Its own session: a Ctrl-C meant for the test is not the daemons'; they
    // die with the test through the parent-death signal instead.
    ::setsid();
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);
    sigset_t all;
    ::sigemptyset(&all);
    ::sigprocmask(SIG_SETMASK, &all, nullptr);
    ::dup2(null, 0);
    ::dup2(out, 1);
    ::dup2(out, 2);
    ::syscall(SYS_close_range, 3U, ~0U, 0U);
    ::execve(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
  const int err = errno;
  ::close(out);
  ::close(null);
  if (pid < 0) {
    if (why) *why = std::string("fork: ") + std::strerror(err);
    return false;
  }
  d.pid = pid;
  started_.push_back(pid);
  return true;
}

bool SlurmCluster::wait_nodes_idle(double timeout_s, std::string* why) {
  std::string last;
  for (const auto t0 = Clock::now();;) {
    for (Daemon* d : std::initializer_list<Daemon*>{&munged_, &ctld_})
      if (d->pid > 0 && ::waitpid(d->pid, nullptr, WNOHANG) == d->pid) {
        d->pid = 0;
        if (why) *why = "SlurmCluster::start: " + d->name + " exited";
        return false;
      }
    for (auto& d : slurmd_)
      if (d.pid > 0 && ::waitpid(d.pid, nullptr, WNOHANG) == d.pid) {
        d.pid = 0;
        if (why) *why = "SlurmCluster::start: slurmd " + d.name + " exited";
        return false;
      }
    int rc = 0;
    last = run("sinfo -h -N -o '%N %t'", &rc);
    int idle = 0;
    std::stringstream ss(last);
    for (std::string node, state; ss >> node >> state;) idle += state == "idle";
    if (rc == 0 && idle == nodes()) return true;
    if (since(t0) > timeout_s) {
      if (why)
        *why = "SlurmCluster::start: the nodes are not all idle after " + std::to_string(timeout_s) + " s; sinfo:\n" +
               last;
      return false;
    }
    sleep_s(0.1);
  }
}

void SlurmCluster::terminate(Daemon& d, double grace_s) {
  if (d.pid <= 0) return;
  ::kill(d.pid, SIGTERM);
  for (const auto t0 = Clock::now(); since(t0) < grace_s; sleep_s(0.02)) {
    const pid_t r = ::waitpid(d.pid, nullptr, WNOHANG);
    if (r == d.pid || (r < 0 && errno == ECHILD)) {
      d.pid = 0;
      return;
    }
  }
  ::kill(d.pid, SIGKILL);
  ::waitpid(d.pid, nullptr, 0);
  d.pid = 0;
}

void SlurmCluster::stop() {
  if (ctld_.pid > 0) {
    // Jobs are ended through Slurm first, so that the slurmstepds clean up
    // while their slurmd still runs; what is left is swept below.
    const std::string ids = run("timeout 5 squeue -h -o %i");
    if (!trim(ids).empty()) {
      std::string list;
      std::stringstream ss(ids);
      for (std::string id; ss >> id;) list += " " + id;
      run("timeout 5 scancel" + list);
      for (const auto t0 = Clock::now(); since(t0) < 2 && !trim(run("timeout 2 squeue -h -o %i")).empty();)
        sleep_s(0.1);
    }
  }
  bool started_any = munged_.pid > 0 || ctld_.pid > 0;
  for (const auto& d : slurmd_) started_any = started_any || d.pid > 0;
  for (auto& d : slurmd_) terminate(d, 5);
  terminate(ctld_, 5);
  terminate(munged_, 5);  // last: the others sign their goodbyes with it
  if (started_any) sweep_leftovers();
}

void SlurmCluster::sweep_leftovers() {
  std::set<std::string> logs = {(dir_ / "slurmctld.log").string(), (dir_ / "slurmctld.out").string(),
                                (dir_ / "munged.out").string()};
  for (int i = 1; i <= nodes(); ++i) {
    logs.insert((dir_ / ("slurmd." + node_name(i) + ".log")).string());
    logs.insert((dir_ / ("slurmd." + node_name(i) + ".out")).string());
  }
  const std::string conf_entry = "SLURM_CONF=" + conf().string();
  const std::string cluster_entry = "SLURM_CLUSTER_NAME=" + conf_value("ClusterName");
  const pid_t self = ::getpid();
  const pid_t own_session = ::getsid(0);
  for (const auto t0 = Clock::now(); since(t0) < 5; sleep_s(0.05)) {
    const std::vector<pid_t> pids = all_pids();
    std::set<pid_t> victims;
    std::set<pid_t> sessions;
    for (pid_t p : pids)
      if (p != self && (holds_open(p, logs) || is_job_of(p, conf_entry, cluster_entry))) {
        victims.insert(p);
        const pid_t s = ::getsid(p);
        if (s > 1 && s != own_session) sessions.insert(s);
      }
    // The rest of the jobs' processes: in the session of their slurmstepd.
    for (pid_t p : pids)
      if (p != self && sessions.count(::getsid(p))) victims.insert(p);
    if (victims.empty()) return;
    for (pid_t p : victims) {
      if (std::find(swept_.begin(), swept_.end(), p) == swept_.end()) swept_.push_back(p);
      ::kill(p, SIGKILL);
      ::waitpid(p, nullptr, WNOHANG);  // ours only if restarted under us; else not our child
    }
  }
}

pid_t SlurmCluster::slurmd_pid(int i) const { return i >= 1 && i <= nodes() ? slurmd_[i - 1].pid : 0; }

void SlurmCluster::kill_node(int i) {
  if (i < 1 || i > nodes() || slurmd_[i - 1].pid <= 0) return;
  Daemon& d = slurmd_[i - 1];
  ::kill(d.pid, SIGKILL);
  ::waitpid(d.pid, nullptr, 0);
  d.pid = 0;
}

bool SlurmCluster::restart_node(int i, std::string* why) {
  if (i < 1 || i > nodes() || !running()) {
    if (why) *why = "SlurmCluster::restart_node: no node " + std::to_string(i);
    return false;
  }
  kill_node(i);
  const std::string name = node_name(i);
  auto start_time = [&] {
    const std::string out = run("scontrol -o show node " + name);
    const auto at = out.find("SlurmdStartTime=");
    return at == std::string::npos ? std::string() : out.substr(at + 16, out.find(' ', at) - at - 16);
  };
  // SlurmdStartTime has whole seconds (local time, as scontrol prints it):
  // the new slurmd starts in a later second, so that its registration shows.
  std::tm old_tm{};
  if (::strptime(node_start_times_[i - 1].c_str(), "%Y-%m-%dT%H:%M:%S", &old_tm)) {
    old_tm.tm_isdst = -1;
    const std::time_t old_t = std::mktime(&old_tm);
    while (std::time(nullptr) <= old_t) sleep_s(0.05);
  }
  if (!spawn(slurmd_[i - 1], why)) return false;
  for (const auto t0 = Clock::now();; sleep_s(0.1)) {
    if (::waitpid(slurmd_[i - 1].pid, nullptr, WNOHANG) == slurmd_[i - 1].pid) {
      slurmd_[i - 1].pid = 0;
      if (why) *why = "SlurmCluster::restart_node: slurmd " + name + " exited\n" + log_tail();
      return false;
    }
    const std::string now = start_time();
    const std::string state = trim(run("sinfo -h -n " + name + " -o %t"));
    const bool responding = state.find('*') == std::string::npos && state.rfind("down", 0) != 0 &&
                            state.rfind("drain", 0) != 0 && state.rfind("fail", 0) != 0 && state.rfind("unk", 0) != 0;
    if (!now.empty() && now != node_start_times_[i - 1] && responding) {
      node_start_times_[i - 1] = now;
      return true;
    }
    if (since(t0) > 20) {
      if (why) *why = "SlurmCluster::restart_node: " + name + " not back after 20 s (" + state + ")\n" + log_tail();
      return false;
    }
  }
}

std::string SlurmCluster::env() const { return "SLURM_CONF=" + shell_quote(conf().string()) + " "; }

std::string SlurmCluster::run(const std::string& cmd, int* rc) const {
  const std::string script = "export SLURM_CONF=" + shell_quote(conf().string()) + "\n{ " + cmd + "\n} 2>&1";
  FILE* pipe = ::popen(script.c_str(), "r");
  if (!pipe) {
    if (rc) *rc = -1;
    return {};
  }
  std::string out;
  std::array<char, 4096> buf;
  for (std::size_t n; (n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0;) out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  if (rc) *rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

std::string SlurmCluster::submit(const std::string& sbatch_args, std::string* why) const {
  int rc = 0;
  const std::string out = trim(run("sbatch --parsable " + sbatch_args, &rc));
  // --parsable: "ID" or "ID;CLUSTER".
  const std::string id = out.substr(0, out.find(';'));
  if (rc != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    if (why) *why = "sbatch " + sbatch_args + ": " + out;
    return {};
  }
  return id;
}

std::string SlurmCluster::job_state(const std::string& id) const {
  int rc = 0;
  const std::string out = trim(run("squeue -h -t all -j " + id + " -o %T", &rc));
  return rc == 0 ? out : std::string();
}

std::string SlurmCluster::wait_ended(const std::string& id, double timeout_s) const {
  for (const auto t0 = Clock::now(); since(t0) < timeout_s; sleep_s(0.05)) {
    const std::string s = job_state(id);
    if (is_ended(s)) return s;
  }
  return {};
}

std::string SlurmCluster::wait_started(const std::string& id, double timeout_s) const {
  for (const auto t0 = Clock::now(); since(t0) < timeout_s; sleep_s(0.02)) {
    const std::string s = job_state(id);
    if (!s.empty() && s != "PENDING" && s != "CONFIGURING") return s;
  }
  return {};
}

std::string SlurmCluster::job_field(const std::string& id, const std::string& key) const {
  std::stringstream ss(run("scontrol -o show job " + id));
  for (std::string tok; ss >> tok;)
    if (tok.rfind(key + "=", 0) == 0) return tok.substr(key.size() + 1);
  return {};
}

std::string SlurmCluster::log_tail(int lines) const {
  std::string out;
  std::vector<fs::path> files = {dir_ / "munged.out", dir_ / "slurmctld.out", dir_ / "slurmctld.log"};
  for (int i = 1; i <= nodes(); ++i) files.push_back(dir_ / ("slurmd." + node_name(i) + ".log"));
  for (const auto& f : files) {
    const std::string t = read_tail(f, lines);
    if (!t.empty()) out += "--- " + f.string() + "\n" + t;
  }
  return out;
}

}  // namespace cgview::test
