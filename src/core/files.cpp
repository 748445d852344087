#include "plumetrace/core/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/version.hpp"

namespace plumetrace {

OutputFile::OutputFile(std::string path) : path_(std::move(path)), part_(path_ + ".part") {
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
