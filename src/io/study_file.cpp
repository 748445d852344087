#include "plumetrace/io/study_file.hpp"

#include <filesystem>
#include <regex>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/toml_input.hpp"

namespace plumetrace {

namespace {

// what `report` may name: a module of the plumetrace package, or a .py file inside the study's
// folder (symbolic links resolved); anything else is refused naming the file and the key
void resolve_report(StudyFile& study, const std::string& folder, const std::string& text) {
  namespace fs = std::filesystem;
  const auto fail = [&](const std::string& why) {
    throw ConfigError(study.file + ": report: '" + text + "' " + why +
                      "; give a module of the plumetrace package (e.g. "
                      "\"plumetrace.studies.meander\") or a .py file of the study's folder (e.g. "
                      "\"report.py\")");
  };
  static const std::regex module(R"(plumetrace(\.[A-Za-z_][A-Za-z0-9_]*)+)");
  if (std::regex_match(text, module)) {
    study.report = text;
    return;
  }
  if (!ends_with(text, ".py")) fail("is not a module of plumetrace nor a .py file");
  const fs::path given(text);
  if (given.is_absolute()) fail("is an absolute path, not a file of the study's folder");
  std::error_code ec;
  const fs::path root = fs::canonical(folder, ec);
  const fs::path file = fs::canonical(fs::path(folder) / given, ec);
  if (ec || !fs::is_regular_file(file)) fail("is not a file of the study's folder");
  const fs::path inside = file.lexically_relative(root);
  if (inside.empty() || *inside.begin() == "..") fail("lies outside the study's folder");
  study.report = (fs::path(folder) / given).lexically_normal().string();
  study.report_is_file = true;
}

}  // namespace

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
      check_printable(study.name, study.file, key);
    } else if (key == "title") {
      study.title = text(node, key);
      check_printable(study.title, study.file, key);
    } else if (key == "report") {
      resolve_report(study, folder, text(node, key));
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
