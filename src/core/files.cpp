#include "plumetrace/core/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/version.hpp"

namespace plumetrace {

namespace {

// a temporary name beside `path` that no other writer uses: this process's id and a count
std::string part_name(const std::string& path) {
  static std::atomic<unsigned long> count{0};
  return path + "." + std::to_string(::getpid()) + "-" + std::to_string(count++) + ".part";
}

}  // namespace

OutputFile::OutputFile(std::string path) : path_(std::move(path)), part_(part_name(path_)) {
  out_.open(part_, std::ios::binary | std::ios::trunc);
  if (!out_) throw IoError("cannot write '" + path_ + "'");
  out_.precision(17);
}

OutputFile::~OutputFile() {
  if (committed_) return;
  out_.close();
  std::remove(part_.c_str());
}

void OutputFile::finish() {
  out_.close();
  if (!out_) throw IoError("error while writing '" + path_ + "' (is the disk full?)");
}

void OutputFile::publish() {
  if (std::rename(part_.c_str(), path_.c_str()) != 0) {
    throw IoError("cannot write '" + path_ + "': " + std::strerror(errno));
  }
  committed_ = true;
}

void OutputFile::commit() {
  finish();
  publish();
}

// why: the type is checked on the open descriptor, opened without blocking, so that a FIFO or a
// device named as an input neither blocks open() or read() for ever nor is swapped in between
// a check and the open (issue 13, F8)
bool read_regular_file(const std::string& path, std::string& text, std::string& why,
                       std::uint64_t max_bytes) {
  // why: the operating system reads a path up to its first NUL, so another file would be read
  if (path.find('\0') != std::string::npos) {
    why = "the path holds a NUL character";
    return false;
  }
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
  const auto too_large = [&](std::uint64_t size) {
    why = "larger than " + std::to_string(max_bytes) +
          " bytes, the most an input file may have (it has " + std::to_string(size) + ")";
    return false;
  };
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
    return too_large(static_cast<std::uint64_t>(st.st_size));
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
    // why: a file that grows while it is read (a log) is bounded too
    if (text.size() > max_bytes) return too_large(text.size());
  }
}

bool is_folder_name(std::string_view name) {
  const auto plain = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  };
  return !name.empty() && name.size() <= kMaxFolderName && name[0] != '.' && name[0] != '-' &&
         std::all_of(name.begin(), name.end(), plain);
}

std::string default_output_folder(const std::string& name, const std::string& file,
                                  const std::string& key) {
  if (!is_folder_name(name)) {
    throw ConfigError(file + ": " + key + ": '" + name +
                      "' cannot be the outputs' folder under out/ (letters, digits, '_', '-' and "
                      "'.', not first, at most " +
                      std::to_string(kMaxFolderName) + " characters); rename it or give --out");
  }
  return "out/" + name;
}

void make_output_folder(const std::string& path, const std::string& what, bool probe) {
  namespace fs = std::filesystem;
  if (path.empty()) throw ConfigError(what + ": must not be empty");
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_directory(status)) {
    throw ConfigError(what + ": '" + path + "' is a file, not a folder");
  }
  fs::create_directories(path, ec);
  if (ec) throw IoError("cannot create the folder '" + path + "' (" + what + "): " + ec.message());
  if (!probe) return;
  // a file created and removed again: rights, a read-only disk or /proc refuse it here
  const std::string test_file = part_name(path + "/.plumetrace-probe");
  const int fd = ::open(test_file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    throw IoError("cannot write in the folder '" + path + "' (" + what +
                  "): " + std::strerror(errno));
  }
  ::close(fd);
  ::unlink(test_file.c_str());
}

std::size_t control_character(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) return i;
    // C1 controls, U+0080-U+009F: 0xC2 0x80-0x9F in UTF-8
    if (c == 0xc2 && i + 1 < text.size()) {
      const auto d = static_cast<unsigned char>(text[i + 1]);
      if (d >= 0x80 && d <= 0x9f) return i;
    }
  }
  return std::string_view::npos;
}

void check_printable(std::string_view text, const std::string& where, const std::string& key) {
  const std::size_t at = control_character(text);
  if (at == std::string_view::npos) return;
  char code[8];
  std::snprintf(code, sizeof code, "0x%02x", static_cast<unsigned char>(text[at]));
  throw ConfigError(where + ": " + key + ": holds a control character (" + code + " at byte " +
                    std::to_string(at) +
                    "); names and titles are printed on terminals and written into CSV and HTML");
}

std::string_view version() { return kVersion; }

void write_text_file(const std::string& path, std::string_view text) {
  OutputFile file(path);
  file.stream() << text;
  file.commit();
}

void check_writable(const std::string& path) { OutputFile probe(path); }

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

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

}  // namespace plumetrace
