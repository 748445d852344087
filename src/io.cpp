#include "plumetrace/io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <utility>

#include "json_util.hpp"
#include "plumetrace/campaign.hpp"
#include "plumetrace/version.hpp"

namespace plumetrace {

namespace {

using detail::number_or_null;
using detail::result_json;
using detail::stats_json;
using detail::value_to_json;
using nlohmann::json;

void flatten(const toml::table& table, const std::string& prefix, const std::string& path,
             Layer layer, std::vector<Setting>& out, int depth = 1) {
  for (const auto& [k, node] : table) {
    const std::string key = prefix + std::string(k.str());
    if (const auto* sub = node.as_table()) {
      // why: each level is a stack frame holding the key so far; a key of 30000 segments would
      // overflow the stack (issue 13, F5)
      if (depth >= kMaxKeyDepth) {
        throw ConfigError(path + ": key '" + key + ".' is nested more than " +
                          std::to_string(kMaxKeyDepth) +
                          " levels deep (config keys are table.key)");
      }
      flatten(*sub, key + ".", path, layer, out, depth + 1);
    } else if (const auto* i = node.as_integer()) {
      out.push_back({key, static_cast<std::int64_t>(i->get()), false, path, layer});
    } else if (const auto* d = node.as_floating_point()) {
      out.push_back({key, d->get(), false, path, layer});
    } else if (const auto* s = node.as_string()) {
      out.push_back({key, s->get(), false, path, layer});
    } else if (const auto* b = node.as_boolean()) {
      out.push_back({key, b->get(), false, path, layer});
    } else {
      // why: let the key's own check reject it, so the message names the key and its range
      // (or says the key is unknown)
      out.push_back(
          {key, std::string(node.is_array() ? "<array>" : "<date or time>"), false, path, layer});
    }
  }
}

// reads the whole of a regular file into `text`; false with the reason in `why` otherwise
// why: the type is checked on the open descriptor, opened without blocking, so that a FIFO or a
// device named as an input neither blocks open() or read() for ever nor is swapped in between
// a check and the open (issue 13, F8)
bool read_regular_file(const std::string& path, std::string& text, std::string& why) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    why = std::strerror(errno);
    return false;
  }
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    why = std::strerror(errno);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    why = S_ISDIR(st.st_mode) ? "a folder, not a file" : "not a regular file";
    return false;
  }
  text.clear();
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n == 0) return true;
    if (n < 0) {
      if (errno == EINTR) continue;
      why = std::strerror(errno);
      return false;
    }
    text.append(buffer, static_cast<std::size_t>(n));
  }
}

// the end of the quoted string that starts at `at` (one of " ' """ '''), or npos when unclosed
std::size_t string_end(std::string_view text, std::size_t at) {
  const char quote = text[at];
  const bool multi = text.substr(at, 3) == std::string(3, quote);
  const bool escapes = quote == '"';
  for (std::size_t i = at + (multi ? 3 : 1); i < text.size(); ++i) {
    if (escapes && text[i] == '\\') {
      ++i;
    } else if (!multi && text[i] == '\n') {
      return std::string_view::npos;
    } else if (text[i] == quote && (!multi || text.substr(i, 3) == std::string(3, quote))) {
      // why: a multi-line string may end in up to two more quotes ("a""" + "" is a"")
      std::size_t end = i + (multi ? 3 : 1);
      while (multi && end < text.size() && text[end] == quote && end < i + 5) ++end;
      return end;
    }
  }
  return std::string_view::npos;
}

// refuses a TOML text with a dotted chain (a.b."c".d, a table header [a.b.c]) of more than
// kMaxKeyDepth parts, naming the line
// why: toml++ nests a table per part and walks the nesting recursively; a key of 60000 parts
// overflows the stack inside toml::parse (issue 13, F5). Counted without parsing: bare words and
// quoted strings joined by dots, outside comments; values form chains of at most two (1.5)
void check_key_depth(std::string_view text, const std::string& path) {
  const auto bare = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '+';
  };
  int parts = 0;           // parts of the chain being read
  bool after_dot = false;  // the chain ends in a dot: the next word or string joins it
  int line = 1;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    std::size_t next = i + 1;
    if (c == '\n') ++line;
    if (c == '#') {
      next = text.find('\n', i);
      if (next == std::string_view::npos) next = text.size();
      parts = 0;
    } else if (c == '"' || c == '\'') {
      const std::size_t end = string_end(text, i);
      if (end == std::string_view::npos) return;  // toml::parse says where
      line += static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(i),
                                          text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
      parts = after_dot ? parts + 1 : 1;
      after_dot = false;
      next = end;
    } else if (bare(c)) {
      while (next < text.size() && bare(text[next])) ++next;
      parts = after_dot ? parts + 1 : 1;
      after_dot = false;
    } else if (c == '.' && parts > 0) {
      after_dot = true;
    } else if (c != ' ' && c != '\t') {
      parts = 0;
      after_dot = false;
    }
    if (parts > kMaxKeyDepth) {
      throw ConfigError(path + ":" + std::to_string(line) + ": a key has more than " +
                        std::to_string(kMaxKeyDepth) + " dotted parts (config keys are table.key)");
    }
    i = next;
  }
}

toml::table parse_toml_file(const std::string& path, const std::string& what) {
  std::string text, why;
  if (!read_regular_file(path, text, why)) {
    throw ConfigError("cannot read " + what + " '" + path + "': " + why);
  }
  check_key_depth(text, path);
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    std::ostringstream msg;
    msg << path << ":" << e.source().begin.line << ":" << e.source().begin.column
        << ": invalid TOML: " << e.description();
    throw ConfigError(msg.str());
  }
}

// a file written whole or not at all: into PATH.part, renamed over PATH by commit(); dropped
// when destroyed uncommitted (an error, an exception)
// why: a reader, or a process killed mid-write (a launcher ending a job), never sees half a file
class OutputFile {
 public:
  explicit OutputFile(std::string path) : path_(std::move(path)), part_(path_ + ".part") {
    out_.open(part_, std::ios::binary | std::ios::trunc);
    if (!out_) throw IoError("cannot write '" + path_ + "'");
    out_.precision(17);
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile() {
    if (committed_) return;
    out_.close();
    std::remove(part_.c_str());
  }
  std::ofstream& stream() { return out_; }
  // writes out what is buffered and checks that every write went through (a full disk fails
  // here); the file is not yet in place
  void finish() {
    out_.close();
    if (!out_) throw IoError("error while writing '" + path_ + "' (is the disk full?)");
  }
  // puts the finished file in place
  void publish() {
    if (std::rename(part_.c_str(), path_.c_str()) != 0) {
      throw IoError("cannot write '" + path_ + "': " + std::strerror(errno));
    }
    committed_ = true;
  }
  void commit() {
    finish();
    publish();
  }

 private:
  std::string path_;
  std::string part_;
  std::ofstream out_;
  bool committed_ = false;
};

// a text field of a CSV file, quoted as RFC 4180 says where it must be: a field holding a comma,
// a double quote or a line break is enclosed in double quotes, with each double quote doubled
std::string csv_text(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + '"';
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::string_view version() { return kVersion; }

void write_text_file(const std::string& path, std::string_view text) {
  OutputFile file(path);
  file.stream() << text;
  file.commit();
}

void check_writable(const std::string& path) { OutputFile probe(path); }

std::vector<Setting> read_scenario_file(const std::string& path) {
  const toml::table table = parse_toml_file(path, "scenario file");
  std::vector<Setting> settings;
  flatten(table, "", path, Layer::kFile, settings);
  return settings;
}

std::vector<std::string> preset_names(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) return names;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const auto& path = entry.path();
    if (entry.is_regular_file(ec) && path.extension() == ".toml") {
      names.push_back(path.stem().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

Reading read_reading(const std::string& folder, const std::string& name) {
  Reading reading{name, "", {}};
  if (name == kDefaultReading) return reading;
  const auto names = preset_names(folder);
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string known = kDefaultReading;
    for (const auto& n : names) known += ", " + n;
    throw ConfigError("unknown preset '" + name + "' (presets: " + known + "; files " + folder +
                      "/NAME.toml)");
  }
  reading.file = folder + "/" + name + ".toml";
  const toml::table table = parse_toml_file(reading.file, "preset file");
  flatten(table, "", reading.file, Layer::kCommandLine, reading.settings);
  // every key and value checked now, naming the file, before any run
  build_scenario(reading.settings);
  return reading;
}

Scenario load_scenario(const std::string& path, const std::vector<Setting>& overrides) {
  std::vector<Setting> settings;
  if (!path.empty()) settings = read_scenario_file(path);
  settings.insert(settings.end(), overrides.begin(), overrides.end());
  return build_scenario(settings);
}

std::string scenario_to_toml(const Scenario& scenario) {
  Scenario copy = scenario;
  std::ostringstream out;
  std::string table;
  for (const auto& f : scenario_fields(copy)) {
    const auto dot = f.key.find('.');
    const std::string t = f.key.substr(0, dot);
    if (t != table) {
      out << (table.empty() ? "" : "\n") << "[" << t << "]\n";
      table = t;
    }
    const ConfigValue v = get_field(scenario, f.key);
    std::string text = std::holds_alternative<std::string>(v)
                           ? "\"" + std::get<std::string>(v) + "\""
                           : format_value(v);
    out << f.key.substr(dot + 1) << " = " << text << "  # " << f.help << "\n";
  }
  return out.str();
}

std::string scenario_to_json(const Scenario& scenario) {
  Scenario copy = scenario;
  json j = json::object();
  for (const auto& f : scenario_fields(copy)) {
    const auto dot = f.key.find('.');
    const ConfigValue v = get_field(scenario, f.key);
    const double* d = std::get_if<double>(&v);
    j[f.key.substr(0, dot)][f.key.substr(dot + 1)] =
        d && std::isinf(*d) ? json(format_number(*d)) : value_to_json(v);
  }
  return j.dump(2);
}

std::string result_to_json(const RunResult& result, const RunInfo& info) {
  return result_json(result, info).dump();
}

std::string probe_to_json(const std::vector<ProbeResult>& results) {
  json points = json::array();
  for (const auto& r : results) {
    points.push_back({{"x", r.point.x},
                      {"y", r.point.y},
                      {"z", r.point.z},
                      {"detect_fraction", r.detect_fraction},
                      {"mean_concentration", r.mean_concentration},
                      {"samples", r.samples}});
  }
  return json{{"points", points}}.dump();
}

void check_trace_path(const std::string& path) {
  if (!ends_with(path, ".csv") && !ends_with(path, ".json")) {
    throw ConfigError("--trace '" + path + "': the name must end in .csv or .json");
  }
  std::vector<std::string> files{path};
  if (ends_with(path, ".csv")) files.push_back(path.substr(0, path.size() - 4) + ".filaments.csv");
  for (const auto& f : files) check_writable(f);
}

void write_trace(const std::string& path, const Trace& trace, const Scenario& scenario,
                 const RunResult& result, const RunInfo& info) {
  if (ends_with(path, ".json")) {
    json steps{{"time", json::array()},
               {"x", json::array()},
               {"y", json::array()},
               {"heading", json::array()},
               {"odometer", json::array()},
               {"state", json::array()},
               {"odor", json::array()},
               {"concentration", json::array()},
               {"wind_samples", json::array()},
               {"wind_x_body", json::array()},
               {"wind_y_body", json::array()},
               {"wind_z_body", json::array()}};
    for (const auto& s : trace.steps) {
      steps["time"].push_back(s.time);
      steps["x"].push_back(s.pose.x);
      steps["y"].push_back(s.pose.y);
      steps["heading"].push_back(s.pose.heading);
      steps["odometer"].push_back(s.odometer);
      steps["state"].push_back(s.state);
      steps["odor"].push_back(s.odor);
      steps["concentration"].push_back(s.concentration);
      steps["wind_samples"].push_back(s.wind_samples);
      const bool sampled = s.wind_samples > 0;
      steps["wind_x_body"].push_back(sampled ? json(s.wind_body.x) : json(nullptr));
      steps["wind_y_body"].push_back(sampled ? json(s.wind_body.y) : json(nullptr));
      steps["wind_z_body"].push_back(sampled ? json(s.wind_body.z) : json(nullptr));
    }
    // why: written a snapshot at a time, as the dump of the whole document would be (keys in
    // nlohmann's order), since the snapshots are most of it and a document of them all held
    // several times the trace's memory
    OutputFile file(path);
    auto& out = file.stream();
    out << R"({"config":)" << json::parse(scenario_to_json(scenario)).dump()
        << R"(,"plumetrace_trace":1,"result":)" << result_json(result, info).dump()
        << R"(,"snapshots":[)";
    for (std::size_t i = 0; i < trace.snapshots.size(); ++i) {
      const auto& snap = trace.snapshots[i];
      if (i > 0) out << ',';
      out << json{{"time", snap.time}, {"x", snap.x}, {"y", snap.y}, {"z", snap.z}, {"w", snap.w}}
                 .dump();
    }
    out << R"(],"steps":)" << steps.dump() << "}\n";
    file.commit();
    return;
  }
  if (!ends_with(path, ".csv")) {
    throw IoError("trace file '" + path + "': the name must end in .csv or .json");
  }
  OutputFile file(path);
  auto& out = file.stream();
  out << "time,x,y,heading,odometer,state,odor,concentration,wind_samples,wind_x_body,"
         "wind_y_body,wind_z_body\n";
  for (const auto& s : trace.steps) {
    out << s.time << ',' << s.pose.x << ',' << s.pose.y << ',' << s.pose.heading << ','
        << s.odometer << ',' << csv_text(s.state) << ',' << (s.odor ? 1 : 0) << ','
        << s.concentration << ',' << s.wind_samples << ',';
    if (s.wind_samples > 0) {
      out << s.wind_body.x << ',' << s.wind_body.y << ',' << s.wind_body.z << '\n';
    } else {
      out << ",,\n";
    }
  }
  const std::string snap_path = path.substr(0, path.size() - 4) + ".filaments.csv";
  OutputFile snap_file(snap_path);
  auto& snaps = snap_file.stream();
  snaps << "time,x,y,z,w\n";
  for (const auto& snap : trace.snapshots) {
    for (std::size_t i = 0; i < snap.x.size(); ++i) {
      snaps << snap.time << ',' << snap.x[i] << ',' << snap.y[i] << ',' << snap.z[i] << ','
            << snap.w[i] << '\n';
    }
  }
  // why: the two files are one trace: both are finished before either is put in place, so a
  // full disk leaves the previous pair (or none), never a trace without its filaments (F17)
  file.finish();
  snap_file.finish();
  snap_file.publish();
  try {
    file.publish();
  } catch (const IoError&) {
    std::remove(snap_path.c_str());
    throw;
  }
}

namespace {

// a config JSON object (nested by table) as settings of one layer, in file order
std::vector<Setting> config_settings(const json& config, const std::string& origin) {
  std::vector<Setting> settings;
  for (const auto& [table, keys] : config.items()) {
    for (const auto& [name, v] : keys.items()) {
      const std::string key = table + "." + name;
      if (v.is_boolean()) {
        settings.push_back({key, v.get<bool>(), false, origin, Layer::kFile});
      } else if (v.is_number_integer() &&
                 (!v.is_number_unsigned() ||
                  v.get<std::uint64_t>() <=
                      static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))) {
        settings.push_back({key, v.get<std::int64_t>(), false, origin, Layer::kFile});
      } else if (v.is_number()) {
        settings.push_back({key, v.get<double>(), false, origin, Layer::kFile});
      } else {
        // why: strings are parsed for the key's type, as "inf" is written for infinite numbers
        settings.push_back({key, v.get<std::string>(), true, origin, Layer::kFile});
      }
    }
  }
  return settings;
}

Outcome outcome_from_name(const std::string& name) {
  for (Outcome o : {Outcome::kRunning, Outcome::kSuccess, Outcome::kWall, Outcome::kTimeout,
                    Outcome::kGaveUp}) {
    if (outcome_name(o) == name) return o;
  }
  throw ConfigError("unknown outcome '" + name + "'");
}

// a whole-number field of a trace, checked to lie in [lo, hi]; why: get<int>() wraps a number
// that does not fit, and truncates 1.5 (issue 13, F18)
template <class T>
T trace_integer(const json& v, const std::string& path, const std::string& field, T lo, T hi) {
  bool ok = false;
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    ok = std::cmp_greater_equal(u, lo) && std::cmp_less_equal(u, hi);
  } else if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    ok = std::cmp_greater_equal(i, lo) && std::cmp_less_equal(i, hi);
  }
  if (!ok) {
    throw ConfigError("trace '" + path + "': " + field + " must be a whole number from " +
                      std::to_string(lo) + " to " + std::to_string(hi) + " (got " + v.dump() + ")");
  }
  return v.get<T>();
}

double number_or_nan(const json& v) {
  return v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>();
}

}  // namespace

RecordedRun read_trace(const std::string& path) {
  if (ends_with(path, ".csv")) {
    throw ConfigError("trace '" + path +
                      "': a CSV trace carries no configuration; write the trace as .json "
                      "(plumetrace run --trace run.json)");
  }
  std::string text, why;
  if (!read_regular_file(path, text, why)) {
    throw IoError("cannot read trace '" + path + "': " + why);
  }
  RecordedRun run;
  try {
    const json doc = json::parse(text);
    if (!doc.is_object() || !doc.contains("plumetrace_trace")) {
      throw ConfigError("trace '" + path + "': not a plumetrace trace (no 'plumetrace_trace' key)");
    }
    run.scenario = build_scenario(config_settings(doc.at("config"), path));

    const json& r = doc.at("result");
    constexpr auto kU64 = std::numeric_limits<std::uint64_t>::max();
    constexpr auto kI64 = std::numeric_limits<std::int64_t>::max();
    constexpr auto kInt = std::numeric_limits<int>::max();
    run.info = {r.at("algorithm").get<std::string>(),
                trace_integer<std::uint64_t>(r.at("seed"), path, "result.seed", 0, kU64),
                trace_integer<std::uint64_t>(r.at("trial"), path, "result.trial", 0, kU64)};
    run.version = r.at("version").get<std::string>();
    run.result.outcome = outcome_from_name(r.at("outcome").get<std::string>());
    run.result.time = r.at("time_s").get<double>();
    run.result.d_t = r.at("d_t").get<double>();
    run.result.d_u = r.at("d_u").get<double>();
    run.result.overhead = number_or_nan(r.at("overhead"));
    run.result.losses = trace_integer<int>(r.at("losses"), path, "result.losses", 0, kInt);
    run.result.odor_fraction = r.at("odor_fraction").get<double>();
    run.result.steps = trace_integer<std::int64_t>(r.at("steps"), path, "result.steps", 0, kI64);
    run.result.wind_samples =
        trace_integer<std::int64_t>(r.at("wind_samples"), path, "result.wind_samples", 0, kI64);
    run.result.seed = run.info.seed;
    run.result.trial = run.info.trial;

    const json& st = doc.at("steps");
    const std::size_t n = st.at("time").size();
    for (const char* column : {"x", "y", "heading", "odometer", "state", "odor", "concentration",
                               "wind_samples", "wind_x_body", "wind_y_body", "wind_z_body"}) {
      if (st.at(column).size() != n) {
        throw ConfigError("trace '" + path + "': column '" + column + "' has " +
                          std::to_string(st.at(column).size()) + " rows, 'time' has " +
                          std::to_string(n));
      }
    }
    if (n == 0) throw ConfigError("trace '" + path + "': no steps");
    run.trace.steps.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      TraceStep& s = run.trace.steps[i];
      s.time = st["time"][i].get<double>();
      s.pose = {st["x"][i].get<double>(), st["y"][i].get<double>(), st["heading"][i].get<double>()};
      s.odometer = st["odometer"][i].get<double>();
      s.state = st["state"][i].get<std::string>();
      s.odor = st["odor"][i].get<bool>();
      s.concentration = st["concentration"][i].get<double>();
      s.wind_samples = trace_integer<int>(st["wind_samples"][i], path,
                                          "steps.wind_samples[" + std::to_string(i) + "]", 0, kInt);
      if (s.wind_samples > 0) {
        s.wind_body = {st["wind_x_body"][i].get<double>(), st["wind_y_body"][i].get<double>(),
                       st["wind_z_body"][i].get<double>()};
      }
    }
    for (const auto& snap : doc.at("snapshots")) {
      FilamentSnapshot f;
      f.time = snap.at("time").get<double>();
      f.x = snap.at("x").get<std::vector<double>>();
      f.y = snap.at("y").get<std::vector<double>>();
      f.z = snap.at("z").get<std::vector<double>>();
      f.w = snap.at("w").get<std::vector<double>>();
      if (f.y.size() != f.x.size() || f.z.size() != f.x.size() || f.w.size() != f.x.size()) {
        throw ConfigError("trace '" + path +
                          "': a filament snapshot has columns of unequal length");
      }
      run.trace.snapshots.push_back(std::move(f));
    }
  } catch (const json::exception& e) {
    throw ConfigError("trace '" + path + "': not a valid plumetrace trace (" + e.what() + ")");
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    if (what.rfind("trace '", 0) == 0) throw;
    throw ConfigError("trace '" + path + "': " + what);
  }
  return run;
}

namespace {

std::optional<ConfigValue> toml_scalar(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<std::int64_t>(i->get());
  if (const auto* d = node.as_floating_point()) return d->get();
  if (const auto* s = node.as_string()) return s->get();
  if (const auto* b = node.as_boolean()) return b->get();
  return std::nullopt;
}

}  // namespace

SweepDef read_sweep_file(const std::string& path) {
  const toml::table table = parse_toml_file(path, "sweep file");
  SweepDef def;
  def.file = path;
  const auto fail = [&](const std::string& msg) { throw ConfigError(path + ": " + msg); };
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  for (const auto& [k, node] : table) {
    const std::string key(k.str());
    if (key == "name" && node.is_string()) {
      def.name = node.as_string()->get();
    } else if (key == "title" && node.is_string()) {
      def.title = node.as_string()->get();
    } else if (key == "scenario" && node.is_string()) {
      const std::filesystem::path p(node.as_string()->get());
      def.scenario_path = (p.is_absolute() ? p : folder / p).lexically_normal().string();
    } else if (key == "runs" && node.is_integer()) {
      const auto runs = node.as_integer()->get();
      if (runs < 1 || runs > kMaxCampaignRuns) {
        fail("runs: must be an integer >= 1 and <= " + std::to_string(kMaxCampaignRuns) + " (got " +
             std::to_string(runs) + ")");
      }
      def.runs = static_cast<int>(runs);
    } else if (key == "seed" && node.is_integer()) {
      const auto seed = node.as_integer()->get();
      if (seed < 0) fail("seed: must be an integer >= 0");
      def.seed = static_cast<std::uint64_t>(seed);
    } else if (key == "set" && node.is_table()) {
      flatten(*node.as_table(), "", path + ": [set]", Layer::kSweep, def.settings);
    } else if (key == "axis" && node.is_array_of_tables()) {
      for (const auto& item : *node.as_array()) {
        Axis axis;
        for (const auto& [ak, anode] : *item.as_table()) {
          const std::string akey(ak.str());
          if (akey == "key" && anode.is_string()) {
            axis.key = anode.as_string()->get();
          } else if (akey == "label" && anode.is_string()) {
            axis.label = anode.as_string()->get();
          } else if (akey == "fixed" && toml_scalar(anode)) {
            axis.fixed = toml_scalar(anode);
          } else if (akey == "values" && anode.is_array()) {
            for (const auto& v : *anode.as_array()) {
              const auto value = toml_scalar(v);
              if (!value) fail("axis values must be numbers or strings");
              axis.values.push_back(*value);
            }
          } else {
            fail("[[axis]]: unknown or mistyped key '" + akey +
                 "' (keys: key = \"dotted.key\", values = [...], label, fixed)");
          }
        }
        if (axis.key.empty()) fail("[[axis]]: missing key = \"dotted.config.key\"");
        if (axis.values.empty()) fail("axis " + axis.key + ": values must not be empty");
        for (const auto& other : def.axes) {
          if (other.key == axis.key) fail("axis " + axis.key + " is given twice");
        }
        if (axis.label.empty()) axis.label = axis.key;
        def.axes.push_back(std::move(axis));
      }
    } else {
      fail("unknown or mistyped key '" + key +
           "' (keys: name, title, scenario, runs, seed, [set], [[axis]])");
    }
  }
  if (def.name.empty()) fail("missing name = \"...\"");
  if (def.axes.empty()) fail("no [[axis]]: a sweep varies at least one key");
  // unknown axis keys and values of the wrong type are found here, naming the axis
  Scenario probe;
  for (const auto& axis : def.axes) {
    for (const auto& v : axis.values) {
      try {
        set_field(probe, axis.key, v);
      } catch (const ConfigError& e) {
        fail("axis " + axis.key + ": " + e.what());
      }
    }
  }
  return def;
}

std::string campaign_definition(const std::vector<ExpandedSweep>& sweeps) {
  json all = json::array();
  for (const auto& s : sweeps) {
    json axes = json::array();
    for (const auto& a : s.def.axes) {
      json values = json::array();
      for (const auto& v : a.values) values.push_back(value_to_json(v));
      axes.push_back({{"key", a.key}, {"values", values}});
    }
    json points = json::array();
    for (const auto& p : s.points) points.push_back(p.config_hash);
    all.push_back({{"name", s.def.name},
                   {"seed", std::to_string(s.def.seed)},
                   {"axes", axes},
                   {"point_configs", points}});
  }
  return json{{"sweeps", all}}.dump();
}

namespace {

std::vector<std::string> axis_keys(const std::vector<ExpandedSweep>& sweeps) {
  std::vector<std::string> keys;
  for (const auto& s : sweeps) {
    for (const auto& a : s.def.axes) {
      if (std::find(keys.begin(), keys.end(), a.key) == keys.end()) keys.push_back(a.key);
    }
  }
  return keys;
}

const ExpandedSweep* find_sweep(const std::vector<ExpandedSweep>& sweeps, const std::string& name) {
  for (const auto& s : sweeps) {
    if (s.def.name == name) return &s;
  }
  return nullptr;
}

// the first columns' names: sweep, point, then one per axis key
std::string axis_header(const std::vector<std::string>& keys) {
  std::string header = "sweep,point";
  for (const auto& k : keys) header += ',' + csv_text(k);
  return header;
}

// the axis columns of one point: its value under each key, empty where the sweep lacks the key
std::string axis_cells(const ExpandedSweep& sweep, int point,
                       const std::vector<std::string>& keys) {
  std::string cells;
  for (const auto& key : keys) {
    cells += ',';
    for (std::size_t a = 0; a < sweep.def.axes.size(); ++a) {
      if (sweep.def.axes[a].key != key) continue;
      const ConfigValue& v = sweep.points[static_cast<std::size_t>(point)].values[a];
      cells += std::holds_alternative<std::string>(v) ? csv_text(std::get<std::string>(v))
                                                      : format_value(v);
    }
  }
  return cells;
}

std::string csv_number(double v) {
  if (!std::isfinite(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

void write_runs_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                    const std::vector<RunRow>& rows) {
  const auto keys = axis_keys(sweeps);
  OutputFile file(path);
  auto& out = file.stream();
  out << axis_header(keys)
      << ",trial,seed,config_hash,outcome,success,time_s,d_t,d_u,overhead,losses,odor_fraction,"
         "steps,wind_samples\n";
  for (const auto& r : rows) {
    const ExpandedSweep* sweep = find_sweep(sweeps, r.sweep);
    if (!sweep || r.point >= static_cast<int>(sweep->points.size())) continue;
    const RunResult& m = r.result;
    out << csv_text(r.sweep) << ',' << r.point << axis_cells(*sweep, r.point, keys) << ','
        << r.trial << ',' << m.seed << ',' << csv_text(r.config_hash) << ','
        << csv_text(outcome_name(m.outcome)) << ',' << (m.outcome == Outcome::kSuccess ? 1 : 0)
        << ',' << csv_number(m.time) << ',' << csv_number(m.d_t) << ',' << csv_number(m.d_u) << ','
        << csv_number(m.overhead) << ',' << m.losses << ',' << csv_number(m.odor_fraction) << ','
        << m.steps << ',' << m.wind_samples << '\n';
  }
  file.commit();
}

void write_summary_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                       const std::vector<RunRow>& rows, int runs_override) {
  const auto keys = axis_keys(sweeps);
  OutputFile file(path);
  auto& out = file.stream();
  out << axis_header(keys)
      << ",runs,successes,walls,timeouts,gave_up,success_rate,success_lo,success_hi,overhead_n,"
         "overhead_mean,overhead_lo,overhead_hi,overhead_median,overhead_q1,overhead_q3,"
         "mean_time,mean_losses\n";
  for (const auto& sweep : sweeps) {
    const int runs = runs_per_point(sweep, runs_override);
    for (const auto& p : sweep.points) {
      const auto results = point_runs(rows, sweep.def.name, p.index, runs);
      const PointStats st = summarize(results);
      out << csv_text(sweep.def.name) << ',' << p.index << axis_cells(sweep, p.index, keys) << ','
          << st.runs << ',' << st.successes << ',' << st.walls << ',' << st.timeouts << ','
          << st.gave_up << ',' << csv_number(st.success_rate) << ',' << csv_number(st.success_ci.lo)
          << ',' << csv_number(st.success_ci.hi) << ',' << st.overhead.n << ','
          << csv_number(st.overhead.mean) << ',' << csv_number(st.overhead.lo) << ','
          << csv_number(st.overhead.hi) << ',' << csv_number(st.overhead_quartiles.median) << ','
          << csv_number(st.overhead_quartiles.q1) << ',' << csv_number(st.overhead_quartiles.q3)
          << ',' << csv_number(st.mean_time) << ',' << csv_number(st.mean_losses) << '\n';
    }
  }
  file.commit();
}

std::string recorded_path(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path normal = fs::path(path).lexically_normal();
  std::error_code ec;
  const fs::path here = fs::current_path(ec);
  if (!normal.is_absolute() || ec) return normal.string();
  const fs::path inside = normal.lexically_relative(here.lexically_normal());
  if (inside.empty() || *inside.begin() == "..") return normal.string();
  return inside.string();
}

void write_results_json(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                        const std::vector<RunRow>& rows, int runs_override) {
  json doc_sweeps = json::array();
  for (const auto& sweep : sweeps) {
    const int runs = runs_per_point(sweep, runs_override);
    json axes = json::array();
    for (const auto& a : sweep.def.axes) {
      json values = json::array();
      for (const auto& v : a.values) values.push_back(value_to_json(v));
      axes.push_back({{"key", a.key},
                      {"label", a.label},
                      {"values", values},
                      {"fixed", a.fixed ? value_to_json(*a.fixed) : json(nullptr)}});
    }
    json points = json::array();
    for (const auto& p : sweep.points) {
      const auto results = point_runs(rows, sweep.def.name, p.index, runs);
      json values = json::array();
      for (const auto& v : p.values) values.push_back(value_to_json(v));
      json run_list = json::array();
      for (const auto& r : results) {
        run_list.push_back(result_json(
            r, {std::string(algorithm_name(p.scenario.controller.algorithm)), r.seed, r.trial}));
      }
      points.push_back({{"index", p.index},
                        {"values", values},
                        {"config_hash", p.config_hash},
                        {"stats", stats_json(summarize(results))},
                        {"runs", run_list}});
    }
    doc_sweeps.push_back({{"name", sweep.def.name},
                          {"title", sweep.def.title},
                          {"file", recorded_path(sweep.def.file)},
                          {"seed", sweep.def.seed},
                          {"runs_per_point", runs},
                          {"axes", axes},
                          {"points", points}});
  }
  OutputFile file(path);
  auto& out = file.stream();
  out << json{{"plumetrace_results", 1},
              {"version", std::string(version())},
              {"sweeps", doc_sweeps}}
             .dump(1)
      << "\n";
  file.commit();
}

}  // namespace plumetrace
