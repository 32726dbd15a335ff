// cgview-server's settings, described once (server/settings.h): the flags
// set what they always did and refuse bad values naming the flag and its
// range, the config file's other sections too, --help lists every flag, and
// docs/DEPLOYMENT.md's tables and the config fuzzer's dictionary are what
// the description says.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "config.h"
#include "config_error.h"
#include "settings.h"

namespace cgview::server {
namespace {

using nlohmann::json;

std::string read_file(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// As cgview-server's command line sets them.
Settings from_flags(const std::vector<std::string>& args) {
  Settings s;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw std::invalid_argument(a + " needs a value");
      return args[++i];
    };
    if (!apply_flag(s, a, value)) throw std::invalid_argument("unknown option " + a);
  }
  return s;
}

std::string flag_error(const std::vector<std::string>& args) {
  try {
    from_flags(args);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(Settings, EveryFlagSetsWhatItDid) {
  // Every flag cgview-server took before server/settings.h, each with a value.
  // clang-format off
  const Settings s = from_flags({
      "--host", "0.0.0.0", "--port", "9000", "--data-dir", "d", "--config", "c.json", "--static-dir", "web",
      "--samples", "none", "--auth", "required", "--max-upload-mb", "16", "--max-header-kb", "16",
      "--max-ws-message-kb", "256", "--request-timeout-s", "10", "--min-body-rate-kb", "32",
      "--idle-timeout-s", "20", "--ws-idle-timeout-s", "40", "--ws-auth-timeout-s", "7",
      "--max-connections-per-ip", "8", "--rate-limit", "2/3", "--tls-cert", "c.pem", "--tls-key", "k.pem",
      "--workers", "3", "--gl-platform", "surfaceless", "--ws-chunk-kb", "64", "--preview-faces", "0",
      "--preview-target", "10", "--worker", "w", "--job-workers", "5", "--job-timeout-s", "60",
      "--job-memory-mb", "512", "--reader", "r", "--upload-timeout-s", "9", "--on-restart", "interrupt",
      "--executor", "slurm", "--job-cpus", "2", "--plugin-dir", "p", "--sandbox", "off"});
  // clang-format on
  const ServerConfig& c = s.server;
  EXPECT_EQ(c.host, "0.0.0.0");
  EXPECT_EQ(c.port, 9000);
  EXPECT_EQ(c.data_dir, "d");
  EXPECT_EQ(s.config_file, "c.json");
  EXPECT_EQ(c.static_dir, "web");
  EXPECT_EQ(s.samples, "none");
  EXPECT_TRUE(c.auth_required);
  EXPECT_EQ(c.max_upload_bytes, std::size_t(16) << 20);
  EXPECT_EQ(c.max_header_bytes, std::size_t(16) << 10);
  EXPECT_EQ(c.max_ws_message_bytes, std::size_t(256) << 10);
  EXPECT_EQ(c.request_timeout_s, 10);
  EXPECT_EQ(c.min_body_rate, 32 * 1024);
  EXPECT_EQ(c.idle_timeout_s, 20);
  EXPECT_EQ(c.ws_idle_timeout_s, 40);
  EXPECT_EQ(c.ws_auth_timeout_s, 7);
  EXPECT_EQ(c.max_connections_per_ip, 8);
  EXPECT_EQ(c.rate_per_s, 2);
  EXPECT_EQ(c.rate_burst, 3);
  EXPECT_EQ(c.tls_cert, "c.pem");
  EXPECT_EQ(c.tls_key, "k.pem");
  EXPECT_EQ(c.workers, 3);
  EXPECT_EQ(c.gl_platform, render::GlPlatform::surfaceless);
  EXPECT_EQ(c.chunk_bytes, std::size_t(64) << 10);
  EXPECT_EQ(c.preview.threshold_faces, 0u);
  EXPECT_EQ(c.preview.target_faces, 10u);
  EXPECT_EQ(c.jobs.worker, "w");
  EXPECT_EQ(c.jobs.max_workers, 5);
  EXPECT_EQ(c.jobs.timeout_s, 60);
  EXPECT_EQ(c.jobs.memory_mb, 512u);
  EXPECT_EQ(c.reader, "r");
  EXPECT_EQ(c.upload_timeout_s, 9);
  EXPECT_FALSE(c.jobs.requeue_on_restart);
  EXPECT_EQ(c.jobs.executor, "slurm");
  EXPECT_EQ(c.jobs.cpus, 2);
  EXPECT_EQ(c.plugin_dir, "p");
  EXPECT_EQ(c.sandbox.mode, "off");
  // A rate alone: a burst of four seconds.
  EXPECT_EQ(from_flags({"--rate-limit", "5"}).server.rate_burst, 20);
}

TEST(Settings, BadFlagsNameTheFlagAndWhatItTakes) {
  EXPECT_EQ(flag_error({"--port", "x"}), "--port needs a number 0..65535, got 'x'");
  EXPECT_EQ(flag_error({"--port", "65536"}), "--port needs a number 0..65535, got '65536'");
  EXPECT_EQ(flag_error({"--max-upload-mb", "0"}), "--max-upload-mb needs a number 1..1048576, got '0'");
  EXPECT_EQ(flag_error({"--port"}), "--port needs a value");
  EXPECT_EQ(flag_error({"--auth", "maybe"}), "--auth is auto or required, got 'maybe'");
  EXPECT_EQ(flag_error({"--sandbox", "no"}), "--sandbox is auto, required or off, got 'no'");
  EXPECT_EQ(flag_error({"--gl-platform", "x11"}), "--gl-platform is auto, device or surfaceless, got 'x11'");
  EXPECT_NE(flag_error({"--rate-limit", "5/0"}).find("--rate-limit is RATE or RATE/BURST"), std::string::npos);
  EXPECT_EQ(flag_error({"--wrokers", "2"}), "unknown option --wrokers");
  // A key of another section is no flag unless it says so.
  EXPECT_EQ(flag_error({"--poll-s", "2"}), "unknown option --poll-s");
}

// The sandbox and slurm sections, read by the same description.
TEST(Settings, TheOtherSectionsOfTheConfigFile) {
  ServerConfig c;
  apply_config(json::parse(R"({"sandbox": {"mode": "required", "processes": 64, "hidden": ["/etc/x"],
    "plugins_without_sandbox": true},
    "slurm": {"partition": "gpu", "sbatch_args": ["--exclusive"], "poll_s": 0.5, "on_lost": "requeue",
    "shared_data": false}})"),
               c);
  EXPECT_EQ(c.sandbox.mode, "required");
  EXPECT_EQ(c.sandbox.processes, 64);
  EXPECT_EQ(c.sandbox.hidden, std::vector<std::filesystem::path>{"/etc/x"});
  EXPECT_TRUE(c.plugins_without_sandbox);
  EXPECT_EQ(c.jobs.slurm.partition, "gpu");
  EXPECT_EQ(c.jobs.slurm.sbatch_args, std::vector<std::string>{"--exclusive"});
  EXPECT_EQ(c.jobs.slurm.poll_s, 0.5);
  EXPECT_TRUE(c.jobs.slurm.requeue_lost);
  EXPECT_FALSE(c.jobs.slurm.shared_data);
  EXPECT_EQ(config_error({{"sandbox", {{"mode", "no"}}}}), R"(sandbox.mode: is "auto", "required" or "off", got "no")");
  EXPECT_EQ(config_error({{"slurm", {{"poll_s", 0.01}}}}), "slurm.poll_s: must be a number 0.05..3600, got 0.01");
  EXPECT_EQ(config_error({{"server", {{"port", 70000}}}}), "server.port: must be an integer 0..65535, got 70000");
  EXPECT_NE(
      config_error({{"slurm", {{"partiton", "gpu"}}}}).find("slurm.partiton: unknown key (the slurm section knows "),
      std::string::npos);
  // Flags only: no keys of the file.
  EXPECT_NE(config_error({{"server", {{"data_dir", "x"}}}}).find("server.data_dir: unknown key"), std::string::npos);
  EXPECT_NE(config_error({{"slurm", "gpu"}}).find("slurm: must be an object"), std::string::npos);
}

TEST(Settings, HelpListsEveryFlag) {
  const std::string help = settings_help();
  for (const SettingRow& r : list_settings()) {
    if (r.flag.empty()) continue;
    EXPECT_NE(help.find("  " + r.flag + " "), std::string::npos) << r.flag;
  }
  EXPECT_NE(help.find("--port N             port; 0 picks a free one (0..65535, default 8080)"), std::string::npos)
      << help;
}

// Each section's table in docs/DEPLOYMENT.md is the generated one: a new
// setting cannot be left out of it.
TEST(Settings, DeploymentTablesAreGenerated) {
  const std::string doc = read_file(std::filesystem::path(CGVIEW_SOURCE_DIR) / "docs" / "DEPLOYMENT.md");
  ASSERT_FALSE(doc.empty());
  std::vector<std::string> sections;
  for (const SettingRow& r : list_settings())
    if (sections.empty() || sections.back() != r.section) sections.push_back(r.section);
  for (const std::string& section : sections) {
    const std::string begin = "<!-- settings: " + section + " (generated: tests/server/settings_test) -->\n";
    const std::string end = "<!-- end of settings: " + section + " -->";
    const std::size_t b = doc.find(begin), e = doc.find(end);
    const std::string expected = settings_markdown(section);
    ASSERT_TRUE(b != std::string::npos && e != std::string::npos && b < e)
        << "docs/DEPLOYMENT.md has no table of the " << section << " section; put this there:\n"
        << begin << expected << end;
    EXPECT_EQ(doc.substr(b + begin.size(), e - b - begin.size()), expected)
        << "docs/DEPLOYMENT.md's table of the " << section << " section is not server/settings.h's; put this there:\n"
        << begin << expected << end;
  }
}

// The config fuzzer's dictionary (tests/fuzz/dict/config.dict) has every
// section, key and choice, so that the fuzzer reaches each setting's checks.
TEST(Settings, FuzzDictionaryHasEveryKey) {
  const std::string dict = read_file(std::filesystem::path(CGVIEW_SOURCE_DIR) / "tests/fuzz/dict/config.dict");
  ASSERT_FALSE(dict.empty());
  std::set<std::string> words = {"limits", "users", "storage_mb", "concurrent_jobs", "plugins", "rate", "burst"};
  for (const SettingRow& r : list_settings()) {
    words.insert(r.section);
    if (r.key.empty()) continue;  // a flag only
    words.insert(r.key);
    words.insert(r.choices.begin(), r.choices.end());
  }
  std::string missing;
  for (const std::string& w : words) {
    const std::string line = "\"\\\"" + w + "\\\"\"\n";  // "\"key\""
    if (dict.find("\n" + line) == std::string::npos) missing += line;
  }
  EXPECT_TRUE(missing.empty()) << "add these lines to tests/fuzz/dict/config.dict:\n" << missing;
}

}  // namespace
}  // namespace cgview::server
