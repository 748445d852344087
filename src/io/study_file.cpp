#include "plumetrace/io/study_file.hpp"

#include <filesystem>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/io/toml_input.hpp"

namespace plumetrace {

StudyFile read_study_file(const std::string& folder) {
  StudyFile study;
  study.file = (std::filesystem::path(folder) / "study.toml").string();
  const toml::table table = detail::parse_toml_file(study.file, "study file");
  const auto fail = [&](const std::string& msg) { throw ConfigError(study.file + ": " + msg); };
  const auto text = [&](const toml::node& node, const std::string& key) {
    if (!node.is_string() || node.as_string()->get().empty()) {
      fail(key + ": must be a non-empty string");
    }
    return node.as_string()->get();
  };
  for (const auto& [k, node] : table) {
    const std::string key(k.str());
    if (key == "name") {
      study.name = text(node, key);
    } else if (key == "title") {
      study.title = text(node, key);
    } else if (key == "report") {
      study.report = text(node, key);
    } else if (key == "sets") {
      const auto* sets = node.as_array();
      if (!sets || sets->empty()) fail("sets: must be a non-empty list of sweep files");
      for (const auto& s : *sets) {
        const std::filesystem::path p(text(s, "sets"));
        study.sets.push_back(
            (p.is_absolute() ? p : std::filesystem::path(folder) / p).lexically_normal().string());
      }
    } else {
      fail("unknown key '" + key + "' (keys: name, title, sets, report)");
    }
  }
  if (study.name.empty()) fail("name: missing");
  if (study.sets.empty()) fail("sets: missing");
  return study;
}

}  // namespace plumetrace
