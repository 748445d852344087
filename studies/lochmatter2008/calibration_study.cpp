#include "lochmatter2008/calibration_study.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string_view>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/toml_input.hpp"

namespace plumetrace {

namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kStudyKeys = {
    "evidenced_only", "fixed",  "name",    "runs",   "search", "seed",     "sets",      "sets_dir",
    "startup_trials", "target", "threads", "trials", "truth",  "unknowns", "validation"};
const std::vector<std::string> kValidationKeys = {"confirm_runs", "runs", "seed", "top"};
const std::vector<std::string> kTargets = {"paper", "synthetic"};

// the search's seed plus this is the validation's default seed (a fresh one)
constexpr std::uint64_t kValidationSeedOffset = 1'000'003;

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

bool contains(const std::vector<std::string>& items, const std::string& item) {
  return std::find(items.begin(), items.end(), item) != items.end();
}

// a text as a message shows it: control characters escaped (\xNN), at most `max` characters
// why: a message goes to a terminal; a file's text must not move its cursor or colour it
std::string printable(std::string_view text, std::size_t max = 80) {
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  for (const char c : text.substr(0, max)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      out += std::string("\\x") + kHex[byte >> 4] + kHex[byte & 0xf];
    } else {
      out += c;
    }
  }
  return text.size() > max ? out + "..." : out;
}

// a TOML node as a message shows it: its value, or what it is
std::string shown(const toml::node& node) {
  if (const auto value = detail::toml_scalar(node)) return printable(format_value(*value));
  if (node.is_array()) return "a list";
  return node.is_table() ? "a table" : "a date or time";
}

// a path relative to `base`, made absolute and resolved as Python's Path.resolve() does (the
// symbolic links of the parts that exist followed)
std::string resolved(const fs::path& base, const std::string& relative) {
  const fs::path path = base / relative;
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  if (ec) absolute = path;
  const fs::path canonical = fs::weakly_canonical(absolute, ec);
  return (ec ? absolute.lexically_normal() : canonical).string();
}

bool is_file(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

// one file (and entry) that messages name, and the checks of its values
class Where {
 public:
  explicit Where(std::string where) : where_(std::move(where)) {}

  [[noreturn]] void fail(const std::string& msg) const { throw ConfigError(where_ + ": " + msg); }

  std::string text(const toml::node& node, const std::string& key) const {
    if (!node.is_string()) fail("'" + key + "' must be a string (got " + shown(node) + ")");
    return node.as_string()->get();
  }

  std::string non_empty_text(const toml::node* node, const std::string& key) const {
    if (!node || !node->is_string() || node->as_string()->get().empty()) {
      fail("'" + key + "' is missing (a non-empty string)");
    }
    return node->as_string()->get();
  }

  // a text naming a file, a folder or a set
  std::string path_text(const toml::node& node, const std::string& key) const {
    std::string path = text(node, key);
    // why: the operating system reads a path up to its first NUL, so another file would be read
    if (path.find('\0') != std::string::npos) fail("'" + key + "' holds a NUL character");
    return path;
  }

  bool flag(const toml::node* node, const std::string& key, const std::string& what) const {
    if (!node) return false;
    if (!node->is_boolean()) fail("'" + key + "' must be " + what + " (got " + shown(*node) + ")");
    return node->as_boolean()->get();
  }

  ConfigValue scalar(const toml::node& node, const std::string& key) const {
    const auto value = detail::toml_scalar(node);
    if (!value) fail("'" + key + "' must be a number, string or boolean (got " + shown(node) + ")");
    return *value;
  }

  // a finite number, an integer where `integer`; kept as written (an integer or a real)
  ConfigValue number(const toml::node* node, const std::string& key, bool integer) const {
    const std::string kind = integer ? "an integer" : "a number";
    if (!node) fail("'" + key + "': must be " + kind + " (missing)");
    if (node->is_integer()) return static_cast<std::int64_t>(node->as_integer()->get());
    if (!integer && node->is_floating_point()) {
      const double x = node->as_floating_point()->get();
      if (!std::isfinite(x)) {
        fail("'" + key + "': must be a finite number (got " + shown(*node) + ")");
      }
      return x;
    }
    fail("'" + key + "': must be " + kind + " (got " + shown(*node) + ")");
  }

  // an integer from 1 to `max`; `fallback` where the key is absent
  std::int64_t positive(const toml::node* node, const std::string& key, std::int64_t fallback,
                        std::int64_t max) const {
    if (!node) return fallback;
    const std::int64_t value = std::get<std::int64_t>(number(node, key, true));
    if (value < 1) fail("'" + key + "': bad range: must be at least 1 (got " + shown(*node) + ")");
    if (value > max) {
      fail("'" + key + "': bad range: must be at most " + std::to_string(max) + " (got " +
           shown(*node) + ")");
    }
    return value;
  }

 private:
  std::string where_;
};

double number_value(const ConfigValue& value) {
  if (const auto* i = std::get_if<std::int64_t>(&value)) return static_cast<double>(*i);
  return std::get<double>(value);
}

bool is_number(const ConfigValue& value) {
  return std::holds_alternative<double>(value) || std::holds_alternative<std::int64_t>(value);
}

// whether two candidate values are the same: numbers to a relative 1e-9, a boolean only another
// equal boolean (as plumetrace.calibrate.study.same_value)
bool same_value(const ConfigValue& a, const ConfigValue& b) {
  if (is_number(a) && is_number(b)) {
    const double x = number_value(a), y = number_value(b);
    if (x == y) return true;
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    return std::fabs(x - y) <= std::max(1e-9 * std::max(std::fabs(x), std::fabs(y)), 1e-12);
  }
  return a == b;
}

CalibrationUnknown read_unknown(const toml::node& node, const Where& where) {
  const toml::table* e = node.as_table();
  if (!e) where.fail("not a table");
  CalibrationUnknown u;
  u.name = where.non_empty_text(e->get("name"), "name");
  u.key = where.non_empty_text(e->get("key"), "key");
  if (const auto* title = e->get("title")) u.title = where.text(*title, "title");
  if (const auto* changes = e->get("changes")) u.changes = where.text(*changes, "changes");
  if (const auto* printed = e->get("printed")) u.printed = where.scalar(*printed, "printed");
  if (const auto* choices = e->get("choices")) {
    const toml::array* list = choices->as_array();
    if (!list || list->empty()) where.fail("'choices' must be a non-empty list");
    for (const auto& c : *list) {
      const auto value = detail::toml_scalar(c);
      if (!value) where.fail("'choices' holds " + shown(c) + "; give numbers or strings");
      u.choices.push_back(*value);
    }
  } else if (e->contains("low") || e->contains("high")) {
    u.integer = where.flag(e->get("int"), "int", "true or false");
    u.log = where.flag(e->get("log"), "log", "true or false");
    u.low = where.number(e->get("low"), "low", u.integer);
    u.high = where.number(e->get("high"), "high", u.integer);
    if (!(number_value(u.low) < number_value(u.high))) {
      where.fail("bad range: low (" + format_value(u.low) + ") must be below high (" +
                 format_value(u.high) + ")");
    }
    if (u.log && number_value(u.low) <= 0) {
      where.fail("bad range: log = true needs low > 0 (got " + format_value(u.low) + ")");
    }
  } else {
    where.fail("give either 'choices' or 'low' and 'high'");
  }
  if (const auto* evidence = e->get("evidence")) {
    const toml::array* list = evidence->as_array();
    if (!list) where.fail("'evidence' must be a list of [[unknown.evidence]] tables");
    for (const auto& item : *list) {
      const toml::table* ev = item.as_table();
      if (!ev || !ev->contains("value")) {
        where.fail("every [[unknown.evidence]] needs a 'value'");
      }
      UnknownEvidence entry{where.scalar(*ev->get("value"), "evidence.value"), "", ""};
      if (const auto* source = ev->get("source")) entry.source = where.text(*source, "source");
      if (const auto* says = ev->get("says")) entry.says = where.text(*says, "says");
      u.evidence.push_back(std::move(entry));
    }
  }
  return u;
}

// the names of the sets of the study in `folder`, from its study.toml's `sets` (file names
// without .toml); none without one
std::vector<std::string> study_set_names(const fs::path& folder) {
  const fs::path file = folder / "study.toml";
  if (!is_file(file)) return {};
  const toml::table doc = detail::parse_toml_file(file.string(), "study file");
  const Where where(file.string());
  std::vector<std::string> names;
  const toml::node* sets = doc.get("sets");
  if (!sets) return names;
  if (!sets->is_array()) where.fail("'sets' must be a list of sweep files");
  for (const auto& s : *sets->as_array()) {
    names.push_back(fs::path(where.path_text(s, "sets")).stem().string());
  }
  return names;
}

// the dotted keys and values of a table (nested tables and dotted keys alike), by key
void flatten_fixed(const toml::table& table, const std::string& prefix, const Where& where,
                   std::map<std::string, ConfigValue>& out) {
  for (const auto& [k, node] : table) {
    const std::string key = prefix + std::string(k.str());
    if (const auto* sub = node.as_table()) {
      flatten_fixed(*sub, key + ".", where, out);
    } else if (!out.emplace(key, where.scalar(node, "fixed." + printable(key))).second) {
      where.fail("'fixed." + printable(key) + "' is given twice");
    }
  }
}

// each unknown offered its evidenced values alone, each once, in the file's order
// why: the default reading may hold only values with evidence (docs/fidelity.md)
void restrict_to_evidence(std::vector<CalibrationUnknown>& unknowns, const Where& where,
                          const std::string& unknowns_file) {
  for (CalibrationUnknown& u : unknowns) {
    std::vector<ConfigValue> values;
    for (const UnknownEvidence& e : u.evidence) {
      const bool seen = std::any_of(values.begin(), values.end(),
                                    [&](const ConfigValue& v) { return same_value(e.value, v); });
      if (!seen) values.push_back(e.value);
    }
    if (values.empty()) {
      where.fail("'evidenced_only': unknown '" + printable(u.name) +
                 "' has no [[unknown.evidence]] entry in '" + unknowns_file + "'");
    }
    // why: `log` and `integer` stay as declared: they are part of the study's definition, which
    // a resumed study must match
    u.choices = std::move(values);
  }
}

// the searched unknowns, in the unknowns file's order
std::vector<CalibrationUnknown> searched_unknowns(const toml::table& doc,
                                                  const CalibrationStudy& study,
                                                  const Where& where) {
  std::vector<std::string> declared;
  for (const auto& u : study.all_unknowns) declared.push_back(u.name);
  std::vector<std::string> search = declared;
  if (const auto* node = doc.get("search")) {
    const toml::array* list = node->as_array();
    if (!list || list->empty()) where.fail("'search' must be a non-empty list of unknown names");
    search.clear();
    for (const auto& item : *list) {
      if (!item.is_string()) where.fail("'search' must be a non-empty list of unknown names");
      const std::string name = item.as_string()->get();
      if (!contains(declared, name)) {
        where.fail("'search' names unknown '" + printable(name) + "', which '" +
                   study.unknowns_file +
                   "' does not declare (it has: " + printable(joined(declared), 1000) + ")");
      }
      if (contains(search, name))
        where.fail("'search' names unknown '" + printable(name) + "' twice");
      search.push_back(name);
    }
  }
  std::vector<CalibrationUnknown> searched;
  for (const auto& u : study.all_unknowns) {
    if (contains(search, u.name)) searched.push_back(u);
  }
  return searched;
}

// the sets to run: the study file's `sets`, else those of the study whose sweep files these are
// (sets/ beside its study.toml, or the folder itself); each with its sweep file
std::vector<std::string> study_sets(const toml::table& doc, const CalibrationStudy& study,
                                    const Where& where) {
  const fs::path sets_dir(study.sets_dir);
  const std::string self = resolved("", study.file);
  std::vector<std::string> names;
  for (const fs::path& folder : {sets_dir.parent_path(), sets_dir}) {
    if (names.empty() && resolved(folder, "study.toml") != self) names = study_set_names(folder);
  }
  std::vector<std::string> sets = names;
  if (const auto* node = doc.get("sets")) {
    const toml::array* list = node->as_array();
    const auto bad = [&] {
      where.fail("'sets' must be a list of set names among " +
                 (names.empty() ? std::string("the sweep files of sets_dir") : joined(names)) +
                 " (got " + shown(*node) + ")");
    };
    if (!list || list->empty()) bad();
    sets.clear();
    for (const auto& item : *list) {
      if (!item.is_string()) bad();
      const std::string name = where.path_text(item, "sets");
      if (!names.empty() && !contains(names, name)) bad();
      if (contains(sets, name)) where.fail("'sets' names set '" + printable(name) + "' twice");
      sets.push_back(name);
    }
  }
  if (sets.empty()) where.fail("'sets' is missing, and no study.toml beside sets_dir lists them");
  for (const auto& name : sets) {
    if (!is_file(sets_dir / (name + ".toml"))) {
      where.fail("'sets_dir': no sweep file " + printable(name) + ".toml in '" + study.sets_dir +
                 "'");
    }
  }
  return sets;
}

// the truth of a synthetic target, and that of no other
void read_truth(const toml::table& doc, CalibrationStudy& study, const Where& where) {
  const toml::node* node = doc.get("truth");
  if (node && !node->is_table()) {
    where.fail("'truth' must be a table of unknown names and values");
  }
  const toml::table empty;
  const toml::table& truth = node ? *node->as_table() : empty;
  if (study.target != "synthetic") {
    if (!truth.empty()) where.fail("'truth' is only for target = \"synthetic\"");
    return;
  }
  if (truth.empty()) where.fail("target = \"synthetic\" needs a [truth] table");
  for (const auto& [k, value] : truth) {
    const std::string name(k.str());
    const bool searched = std::any_of(study.unknowns.begin(), study.unknowns.end(),
                                      [&](const CalibrationUnknown& u) { return u.name == name; });
    if (!searched) where.fail("'truth' names '" + printable(name) + "', which is not searched");
    study.truth.emplace_back(name, where.scalar(value, "truth." + printable(name)));
  }
}

void read_validation(const toml::table& doc, CalibrationStudy& study, const Where& where) {
  const toml::node* node = doc.get("validation");
  if (node && !node->is_table()) where.fail("'validation' must be a table");
  const toml::table empty;
  const toml::table& val = node ? *node->as_table() : empty;
  for (const auto& [k, value] : val) {
    if (!contains(kValidationKeys, std::string(k.str()))) {
      where.fail("unknown key 'validation." + printable(k.str()) +
                 "' (keys: " + joined(kValidationKeys) + ")");
    }
  }
  CalibrationValidation& v = study.validation;
  v.top = where.positive(val.get("top"), "validation.top", v.top, kMaxCalibrationTrials);
  v.runs = static_cast<int>(
      where.positive(val.get("runs"), "validation.runs", v.runs, kMaxCampaignRuns));
  v.seed =
      static_cast<std::uint64_t>(where.positive(val.get("seed"), "validation.seed", 0, INT64_MAX));
  if (const toml::node* c = val.get("confirm_runs")) {
    v.confirm_runs = static_cast<int>(
        where.positive(c, "validation.confirm_runs", 0, kMaxCampaignRuns));
    if (v.confirm_runs <= v.runs) {
      where.fail("'validation.confirm_runs' (" + std::to_string(v.confirm_runs) +
                 ") must be more than 'validation.runs' (" + std::to_string(v.runs) + ")");
    }
  }
  // why: unsigned, so the default cannot overflow (a seed is at most 2^63 - 1)
  if (v.seed == 0) v.seed = study.seed + kValidationSeedOffset;
  if (v.seed == study.seed) {
    where.fail("'validation.seed' must differ from 'seed' (a fresh seed)");
  }
}

// runs per value times the sets' points, for the search and for the validation, against the
// most runs one evaluation may define
// why: checked here, before the study's database exists; inside each trial a refused size
// failed every candidate and left a database that the corrected study could not resume (G9)
void check_evaluation_size(const CalibrationStudy& study, const Where& where) {
  std::int64_t points = 0;
  for (const auto& name : study.sets) {
    points += grid_points(read_sweep_file((fs::path(study.sets_dir) / (name + ".toml")).string()));
  }
  const std::pair<const char*, int> runs[] = {
      {"runs", study.runs},
      {"validation.runs", study.validation.runs},
      {"validation.confirm_runs", study.validation.confirm_runs}};
  for (const auto& [key, per_value] : runs) {
    const std::int64_t total = points * per_value;
    if (total > kMaxCampaignRuns) {
      where.fail("'" + std::string(key) + "': " + std::to_string(per_value) +
                 " runs per value over the " + std::to_string(points) + " points of sets " +
                 joined(study.sets) + " make " + std::to_string(total) + " runs, more than the " +
                 std::to_string(kMaxCampaignRuns) + " one evaluation may run");
    }
  }
}

}  // namespace

std::vector<CalibrationUnknown> read_calibration_unknowns(const std::string& path) {
  const toml::table doc = detail::parse_toml_file(path, "unknowns file");
  const std::string file = "unknowns file '" + path + "'";
  const toml::array* entries = doc.get("unknown") ? doc.get("unknown")->as_array() : nullptr;
  if (!entries || entries->empty()) throw ConfigError(file + ": no [[unknown]] entries");
  std::vector<CalibrationUnknown> unknowns;
  for (std::size_t i = 0; i < entries->size(); ++i) {
    const toml::node& node = *entries->get(i);
    const toml::node* name = node.is_table() ? node.as_table()->get("name") : nullptr;
    const std::string label =
        name && name->is_string() ? name->as_string()->get() : std::to_string(i + 1);
    const Where where(file + ", unknown " + printable(label));
    CalibrationUnknown u = read_unknown(node, where);
    for (const auto& earlier : unknowns) {
      if (earlier.name == u.name) where.fail("name '" + printable(u.name) + "' is used twice");
    }
    unknowns.push_back(std::move(u));
  }
  return unknowns;
}

CalibrationStudy read_calibration_study(const std::string& path) {
  // why: the operating system reads a path up to its first NUL, so another file would be read
  // (shown as \0: a message, a C string, would end there too)
  if (const auto nul = path.find('\0'); nul != std::string::npos) {
    std::string shown = path;
    for (auto at = nul; at != std::string::npos; at = shown.find('\0', at)) {
      shown.replace(at, 1, "\\0");
    }
    throw ConfigError("cannot read study file '" + shown + "': the path holds a NUL character");
  }
  const toml::table doc = detail::parse_toml_file(path, "study file");
  const Where where("study file '" + path + "'");
  for (const auto& [k, node] : doc) {
    if (!contains(kStudyKeys, std::string(k.str()))) {
      where.fail("unknown key '" + printable(k.str()) + "' (keys: " + joined(kStudyKeys) + ")");
    }
  }
  const toml::node* unknowns = doc.get("unknowns");
  if (!unknowns || !unknowns->is_string()) {
    where.fail("'unknowns' is missing: the path of the unknowns file");
  }
  CalibrationStudy study;
  study.file = path;
  const fs::path base = fs::path(path).parent_path();
  study.unknowns_file = resolved(base, where.path_text(*unknowns, "unknowns"));
  study.all_unknowns = read_calibration_unknowns(study.unknowns_file);

  // the searched unknowns, restricted to their evidence where the file asks
  study.unknowns = searched_unknowns(doc, study, where);
  if (where.flag(doc.get("evidenced_only"), "evidenced_only", "true or false")) {
    restrict_to_evidence(study.unknowns, where, study.unknowns_file);
  }
  for (std::size_t i = 0; i < study.unknowns.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (study.unknowns[i].key == study.unknowns[j].key) {
        where.fail("two searched unknowns set the same key '" + printable(study.unknowns[i].key) +
                   "'");
      }
    }
  }

  // the sets and their folder
  const toml::node* sets_dir = doc.get("sets_dir");
  study.sets_dir = sets_dir ? resolved(base, where.path_text(*sets_dir, "sets_dir"))
                            : fs::path(study.unknowns_file).parent_path().string();
  study.sets = study_sets(doc, study, where);

  // the scalars
  if (const auto* name = doc.get("name")) {
    if (!name->is_string() || name->as_string()->get().empty()) {
      where.fail("'name' must be a non-empty string");
    }
    study.name = name->as_string()->get();
  }
  study.runs =
      static_cast<int>(where.positive(doc.get("runs"), "runs", study.runs, kMaxCampaignRuns));
  study.trials = where.positive(doc.get("trials"), "trials", study.trials, kMaxCalibrationTrials);
  study.startup_trials = where.positive(doc.get("startup_trials"), "startup_trials",
                                        study.startup_trials, kMaxCalibrationTrials);
  study.seed = static_cast<std::uint64_t>(
      where.positive(doc.get("seed"), "seed", static_cast<std::int64_t>(study.seed), INT64_MAX));
  if (const auto* threads = doc.get("threads")) {
    const std::int64_t n = std::get<std::int64_t>(where.number(threads, "threads", true));
    if (n < 0 || n > kMaxThreads) {
      where.fail("'threads': bad range: must be 0 (all cores) to " + std::to_string(kMaxThreads) +
                 " (got " + shown(*threads) + ")");
    }
    study.threads = static_cast<int>(n);
  }
  if (const auto* target = doc.get("target")) {
    if (!target->is_string() || !contains(kTargets, target->as_string()->get())) {
      where.fail("'target' must be one of " + joined(kTargets) + " (got " + shown(*target) + ")");
    }
    study.target = target->as_string()->get();
  }
  read_truth(doc, study, where);

  // the fixed settings, none of them searched
  if (const auto* fixed = doc.get("fixed")) {
    if (!fixed->is_table()) where.fail("'fixed' must be a table of config keys and values");
    std::map<std::string, ConfigValue> settings;
    flatten_fixed(*fixed->as_table(), "", where, settings);
    for (const auto& setting : settings) {
      const std::string& key = setting.first;
      const bool searched = std::any_of(study.unknowns.begin(), study.unknowns.end(),
                                        [&](const CalibrationUnknown& u) { return u.key == key; });
      if (searched) where.fail("'fixed." + printable(key) + "' is also a searched unknown");
      study.fixed.push_back(setting);
    }
  }
  read_validation(doc, study, where);
  check_evaluation_size(study, where);
  return study;
}

}  // namespace plumetrace
