#include "plumetrace/io/toml_input.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"

namespace plumetrace::detail {

namespace {

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

}  // namespace

void flatten(const toml::table& table, const std::string& prefix, const std::string& path,
             Layer layer, std::vector<Setting>& out, int depth) {
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

std::optional<ConfigValue> toml_scalar(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<std::int64_t>(i->get());
  if (const auto* d = node.as_floating_point()) return d->get();
  if (const auto* s = node.as_string()) return s->get();
  if (const auto* b = node.as_boolean()) return b->get();
  return std::nullopt;
}

}  // namespace plumetrace::detail
