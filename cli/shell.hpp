#pragma once

#include <string>

namespace plumetrace::cli {

/// `text` as one word of a POSIX shell, for commands a user may paste: plain words as they are,
/// anything else in single quotes.
std::string shell_word(const std::string& text);

}  // namespace plumetrace::cli
