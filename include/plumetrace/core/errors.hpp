#pragma once

#include <stdexcept>

namespace plumetrace {

/// A bad configuration: names the dotted key (or file) and what is allowed.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file that cannot be read or written; the message names the file.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace plumetrace
