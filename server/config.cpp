#include "config.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "auth.h"
#include "core/errors.h"
#include "io/parse_json.h"

namespace cgview::server {

using nlohmann::json;

namespace {

[[noreturn]] void bad(const std::string& key, const std::string& why) { throw std::invalid_argument(key + ": " + why); }

// 65535, 1099511627776, 0.05
std::string number_text(double x) {
  char buf[32];
  if (x == std::floor(x) && std::abs(x) < 1e15) std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(x));
  else std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string range(const SettingInfo& i) { return number_text(i.min) + ".." + number_text(i.max); }

// "a, b or c", each name between `quote`s.
std::string either(const std::vector<std::string>& names, const std::string& quote = "") {
  std::string s;
  for (std::size_t k = 0; k < names.size(); ++k)
    s += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + quote + names[k] + quote;
  return s;
}

template <class T>
std::vector<std::string> names(const std::vector<std::pair<std::string, T>>& options) {
  std::vector<std::string> n;
  for (const auto& o : options) n.push_back(o.first);
  return n;
}

// Its own flag; in the server section "--" and its key with '-' for '_'.
std::string flag_of(const std::string& section, const std::string& key, const SettingInfo& i) {
  if (!i.flag.empty() || section != "server") return i.flag;
  std::string f = "--" + key;
  std::replace(f.begin(), f.end(), '_', '-');
  return f;
}

std::int64_t integer_of(const json& v, const std::string& key, double lo, double hi) {
  if (!v.is_number_integer() || v.get<std::int64_t>() < lo || v.get<std::int64_t>() > hi)
    bad(key, "must be an integer " + number_text(lo) + ".." + number_text(hi) + ", got " + v.dump());
  return v.get<std::int64_t>();
}

std::string string_of(const json& v, const std::string& key) {
  if (!v.is_string()) bad(key, "must be a string, got " + v.dump());
  return v.get<std::string>();
}

const json& object_of(const json& v, const std::string& key) {
  if (!v.is_object()) bad(key, "must be an object, got " + v.dump());
  return v;
}

bool boolean_of(const json& v, const std::string& key) {
  if (!v.is_boolean()) bad(key, "must be true or false, got " + v.dump());
  return v.get<bool>();
}

// Sets each setting whose key the config document has, and learns each
// section's keys (for the unknown ones).
class FileReader {
 public:
  explicit FileReader(const json& doc) : doc_(doc) {}
  std::vector<std::pair<std::string, std::vector<std::string>>> sections;  // their keys
  const std::vector<std::string>* keys_of(const std::string& section) const {
    for (const auto& [name, keys] : sections)
      if (name == section) return &keys;
    return nullptr;
  }

  void section(const char* name) {
    sections.push_back({name, {}});
    const auto it = doc_.find(name);
    body_ = it == doc_.end() ? nullptr : &object_of(*it, name);
  }
  void heading(const char*) {}
  template <class T>
  void integer(const char* key, T& field, const SettingInfo& i) {
    if (const json* v = find(key, i)) field = static_cast<T>(integer_of(*v, where(key), i.min, i.max) * i.unit);
  }
  void number(const char* key, double& field, const SettingInfo& i) {
    if (const json* v = find(key, i)) {
      if (!v->is_number() || !(v->get<double>() >= i.min) || !(v->get<double>() <= i.max))
        bad(where(key), "must be a number " + range(i) + ", got " + v->dump());
      field = v->get<double>();
    }
  }
  void boolean(const char* key, bool& field, const SettingInfo& i) {
    if (const json* v = find(key, i)) field = boolean_of(*v, where(key));
  }
  template <class T>
  void choice(const char* key, T& field, const std::vector<std::pair<std::string, T>>& options, const SettingInfo& i) {
    if (const json* v = find(key, i)) {
      const std::string name = string_of(*v, where(key));
      for (const auto& [n, value] : options)
        if (n == name) return void(field = value);
      bad(where(key), "is " + either(names(options), "\"") + ", got " + v->dump());
    }
  }
  template <class T>
  void text(const char* key, T& field, const SettingInfo& i) {
    if (const json* v = find(key, i)) field = string_of(*v, where(key));
  }
  template <class T>
  void texts(const char* key, std::vector<T>& field, const SettingInfo& i) {
    if (const json* v = find(key, i)) {
      if (!v->is_array()) bad(where(key), "must be a list of strings, got " + v->dump());
      field.clear();
      for (const json& x : *v) field.push_back(string_of(x, where(key)));
    }
  }
  // {"rate": R, "burst": B}; without a burst, as --rate-limit R.
  void rate(const char* key, double& rate, double& burst, const SettingInfo& i) {
    const json* v = find(key, i);
    if (!v) return;
    bool burst_given = false;
    for (const auto& [k, x] : object_of(*v, where(key)).items()) {
      if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < (k == "burst" ? 1 : 0))
        bad(where(key) + "." + k, "must be a number (rate >= 0, burst >= 1), got " + x.dump());
      if (k == "rate") rate = x.get<double>();
      else if (k == "burst") burst = x.get<double>(), burst_given = true;
      else bad(where(key) + "." + k, "unknown key (" + std::string(key) + " has rate and burst)");
    }
    if (!burst_given) burst = std::max(1.0, rate * 4);
  }

 private:
  std::string where(const char* key) const { return sections.back().first + "." + key; }
  const json* find(const char* key, const SettingInfo& i) {
    if (!i.file) return nullptr;
    sections.back().second.push_back(key);
    if (!body_) return nullptr;
    const auto it = body_->find(key);
    return it == body_->end() ? nullptr : &*it;
  }
  const json& doc_;
  const json* body_ = nullptr;
};

// Sets the one setting whose flag is `flag`.
class FlagReader {
 public:
  FlagReader(const std::string& flag, const std::function<std::string()>& value) : flag_(flag), value_(value) {}
  bool found = false;

  void section(const char* name) { section_ = name; }
  void heading(const char*) {}
  template <class T>
  void integer(const char* key, T& field, const SettingInfo& i) {
    if (!is(key, i)) return;
    const std::string v = value_();
    char* end = nullptr;
    const long long n = std::strtoll(v.c_str(), &end, 10);
    if (v.empty() || *end || n < i.min || n > i.max) fail("needs a number " + range(i) + ", got '" + v + "'");
    field = static_cast<T>(n * i.unit);
  }
  void number(const char* key, double& field, const SettingInfo& i) {
    if (!is(key, i)) return;
    const std::string v = value_();
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end || !(x >= i.min) || !(x <= i.max)) fail("needs a number " + range(i) + ", got '" + v + "'");
    field = x;
  }
  void boolean(const char* key, bool& field, const SettingInfo& i) {
    if (!is(key, i)) return;
    const std::string v = value_();
    if (v != "true" && v != "false") fail("is true or false, got '" + v + "'");
    field = v == "true";
  }
  template <class T>
  void choice(const char* key, T& field, const std::vector<std::pair<std::string, T>>& options, const SettingInfo& i) {
    if (!is(key, i)) return;
    const std::string v = value_();
    for (const auto& [n, value] : options)
      if (n == v) return void(field = value);
    fail("is " + either(names(options)) + ", got '" + v + "'");
  }
  template <class T>
  void text(const char* key, T& field, const SettingInfo& i) {
    if (is(key, i)) field = value_();
  }
  template <class T>
  void texts(const char* key, std::vector<T>& field, const SettingInfo& i) {
    if (is(key, i)) field.push_back(value_());  // one more each time the flag is given
  }
  // R or R/B; a burst of four seconds by default.
  void rate(const char* key, double& rate, double& burst, const SettingInfo& i) {
    if (!is(key, i)) return;
    const std::string v = value_();
    char* end = nullptr;
    rate = std::strtod(v.c_str(), &end);
    burst = *end == '/' ? std::strtod(end + 1, &end) : std::max(1.0, rate * 4);
    if (v.empty() || *end || !(rate >= 0) || !(burst >= 1) || rate > 1e9 || burst > 1e9)
      fail("is RATE or RATE/BURST (requests per second, burst >= 1), got '" + v + "'");
  }

 private:
  bool is(const char* key, const SettingInfo& i) {
    if (found || flag_of(section_, key, i) != flag_) return false;
    return found = true;
  }
  [[noreturn]] void fail(const std::string& why) const { throw std::invalid_argument(flag_ + " " + why); }
  const std::string& flag_;
  const std::function<std::string()>& value_;
  std::string section_;
};

// Each setting as a row for people.
class Lister {
 public:
  std::vector<SettingRow> rows;

  void section(const char* name) { section_ = name; }
  void heading(const char* text) { heading_ = text; }
  template <class T>
  void integer(const char* key, T& field, const SettingInfo& i) {
    add(key, i, "N", range(i), number_text(double(field) / double(i.unit)));
  }
  void number(const char* key, double& field, const SettingInfo& i) { add(key, i, "N", range(i), number_text(field)); }
  void boolean(const char* key, bool& field, const SettingInfo& i) {
    add(key, i, "true|false", "`true`, `false`", field ? "true" : "false");
  }
  template <class T>
  void choice(const char* key, T& field, const std::vector<std::pair<std::string, T>>& options, const SettingInfo& i) {
    std::string arg, values, value;
    for (const auto& [n, v] : options) {
      arg += (arg.empty() ? "" : "|") + n;
      values += (values.empty() ? "`" : ", `") + n + "`";
      if (v == field) value = n;
    }
    add(key, i, arg, values, value).choices = names(options);
  }
  template <class T>
  void text(const char* key, T& field, const SettingInfo& i) {
    const bool path = std::is_same_v<T, std::filesystem::path>;
    add(key, i, path ? "PATH" : "TEXT", path ? "a path" : "text", std::filesystem::path(field).string());
  }
  template <class T>
  void texts(const char* key, std::vector<T>& field, const SettingInfo& i) {
    const bool path = std::is_same_v<T, std::filesystem::path>;
    add(key, i, path ? "PATH" : "TEXT", path ? "a list of paths" : "a list of strings", field.empty() ? "none" : "");
  }
  void rate(const char* key, double& rate, double& burst, const SettingInfo& i) {
    add(key, i, "R[/B]", "`R` or `R/B` (in the file `{\"rate\": R, \"burst\": B}`)",
        number_text(rate) + "/" + number_text(burst));
  }

 private:
  SettingRow& add(const char* key, const SettingInfo& i, const std::string& arg, const std::string& values,
                  const std::string& value) {
    rows.push_back({.section = section_,
                    .key = i.file ? key : "",
                    .flag = flag_of(section_, key, i),
                    .arg = i.arg.empty() ? arg : i.arg,
                    .values = values,
                    .default_value = i.default_text.empty() ? value : i.default_text,
                    .help = i.help,
                    .heading = std::exchange(heading_, ""),
                    .choices = {}});
    return rows.back();
  }
  std::string section_, heading_;
};

// storage_mb: a number of MB (fractions allowed), or null (unlimited).
std::optional<std::uint64_t> storage(const json& v, const std::string& key) {
  if (v.is_null()) return std::nullopt;
  if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0 || v.get<double>() > 1e12)
    bad(key, "must be a number of MB >= 0, or null (unlimited), got " + v.dump());
  return std::uint64_t(std::llround(v.get<double>() * double(1 << 20)));
}

std::optional<int> jobs(const json& v, const std::string& key) {
  if (v.is_null()) return std::nullopt;
  return int(integer_of(v, key, 0, 1 << 20));
}

}  // namespace

void apply_config(const json& doc, ServerConfig& config) {
  object_of(doc, "the config");
  Settings settings{.server = config};
  FileReader reader(doc);
  settings.describe(reader);
  for (const auto& [section, body] : doc.items()) {
    if (const std::vector<std::string>* keys = reader.keys_of(section)) {
      for (const auto& [key, v] : body.items())
        if (std::find(keys->begin(), keys->end(), key) == keys->end()) {
          std::string known;
          for (const std::string& k : *keys) known += (known.empty() ? "" : ", ") + k;
          bad(section + "." + key, "unknown key (the " + section + " section knows " + known + ")");
        }
    } else if (section == "limits") {
      for (const auto& [key, v] : object_of(body, section).items()) {
        if (key == "storage_mb") settings.server.jobs.quotas.defaults.storage_bytes = storage(v, "limits." + key);
        else if (key == "concurrent_jobs")
          settings.server.jobs.quotas.defaults.concurrent_jobs = jobs(v, "limits." + key);
        else if (key == "plugins") settings.server.jobs.quotas.defaults.plugins = boolean_of(v, "limits." + key);
        else bad("limits." + key, "unknown key (limits are storage_mb, concurrent_jobs and plugins)");
      }
    } else if (section == "users") {
      for (const auto& [name, limits] : object_of(body, section).items()) {
        const std::string where = "users." + name;
        if (name != "local" && !valid_user_name(name)) bad(where, "'" + name + "' is not a user name");
        UserOverride& o = settings.server.jobs.quotas.users[name];
        for (const auto& [key, v] : object_of(limits, where).items()) {
          if (key == "storage_mb") o.storage_bytes = storage(v, where + "." + key);
          else if (key == "concurrent_jobs") o.concurrent_jobs = jobs(v, where + "." + key);
          else if (key == "plugins") o.plugins = boolean_of(v, where + "." + key);
          else bad(where + "." + key, "unknown key (a user's limits are storage_mb, concurrent_jobs and plugins)");
        }
      }
    } else {
      std::vector<std::string> known;
      for (const auto& s : reader.sections) known.push_back(s.first);
      known.insert(known.end(), {"limits", "users"});
      bad(section, "unknown key (the sections are " + either(known) + ")");
    }
  }
  config = std::move(settings.server);
}

void load_config_file(const std::filesystem::path& file, ServerConfig& config) {
  std::ifstream f(file, std::ios::binary);
  if (!f) throw std::invalid_argument(file.string() + ": cannot read the config file");
  std::stringstream s;
  s << f.rdbuf();
  json doc;
  try {
    doc = parse_json(s.str(), file.string());
  } catch (const json::parse_error& e) {
    throw std::invalid_argument(file.string() + ": not JSON: " + e.what());
  } catch (const InvalidInput& e) {
    throw std::invalid_argument(e.what());
  }
  try {
    apply_config(doc, config);
  } catch (const std::exception& e) {
    throw std::invalid_argument(file.string() + ": " + e.what());
  }
}

bool apply_flag(Settings& settings, const std::string& flag, const std::function<std::string()>& value) {
  if (!flag.starts_with("--")) return false;
  FlagReader reader(flag, value);
  settings.describe(reader);
  return reader.found;
}

std::vector<SettingRow> list_settings() {
  Settings defaults;
  Lister lister;
  defaults.describe(lister);
  return lister.rows;
}

std::string settings_help() {
  constexpr std::size_t kIndent = 23, kWidth = 100;
  std::string out;
  for (const SettingRow& r : list_settings()) {
    if (r.flag.empty()) continue;
    if (!r.heading.empty()) out += "\n" + r.heading + "\n";
    std::string line = "  " + r.flag + " " + r.arg;
    line.resize(std::max(line.size() + 2, kIndent), ' ');
    std::string say = r.help;
    if (!r.default_value.empty() || r.values.find("..") != std::string::npos) {
      say += " (";
      if (r.values.find("..") != std::string::npos) say += r.values + (r.default_value.empty() ? "" : ", ");
      if (!r.default_value.empty()) say += "default " + r.default_value;
      say += ")";
    }
    // Word-wrapped, the lines after the first under the first.
    std::istringstream words(say);
    bool first = true;
    for (std::string w; words >> w; first = false) {
      if (!first && line.size() + 1 + w.size() > kWidth) {
        out += line + "\n";
        line = std::string(kIndent, ' ');
      } else if (!first) {
        line += ' ';
      }
      line += w;
    }
    out += line + "\n";
  }
  return out;
}

std::string settings_markdown(const std::string& section) {
  std::vector<SettingRow> rows = list_settings();
  std::erase_if(rows, [&](const SettingRow& r) { return r.section != section; });
  const bool flags = std::any_of(rows.begin(), rows.end(), [](const SettingRow& r) { return !r.flag.empty(); });
  auto cell = [](const std::string& s) {  // " s |", its pipes escaped
    std::string c = " ";
    for (char ch : s) {
      if (ch == '|') c += '\\';
      c += ch;
    }
    return c + " |";
  };
  std::string out = flags ? "| Key | Flag | Values | Default | What |\n|---|---|---|---|---|\n"
                          : "| Key | Values | Default | What |\n|---|---|---|---|\n";
  for (const SettingRow& r : rows) {
    out += '|';
    out += cell(r.key.empty() ? "(a flag only)" : "`" + r.key + "`");
    if (flags) out += cell(r.flag.empty() ? "" : "`" + r.flag + " " + r.arg + "`");
    out += cell(r.values) + cell(r.default_value) + cell(r.help) + "\n";
  }
  return out;
}

}  // namespace cgview::server
