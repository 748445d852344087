#pragma once

#include <fstream>
#include <string>
#include <string_view>

namespace plumetrace {

/// The program version.
std::string_view version();

/// A file written whole or not at all: into `PATH.part`, renamed over `PATH` by commit(); dropped
/// when destroyed uncommitted (an error, an exception). why: a reader, or a process killed while
/// writing (a launcher ending a job), never sees half a file.
class OutputFile {
 public:
  /// Opens `path`.part for writing (17 significant digits); throws IoError naming `path`.
  explicit OutputFile(std::string path);
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();
  /// The stream to write to.
  std::ofstream& stream() { return out_; }
  /// Writes out what is buffered and checks that every write went through (a full disk fails
  /// here); the file is not yet in place.
  void finish();
  /// Puts the finished file in place.
  void publish();
  /// finish() then publish().
  void commit();

 private:
  std::string path_;
  std::string part_;
  std::ofstream out_;
  bool committed_ = false;
};

/// Every file this library writes is written whole or not at all (OutputFile). Writes `text` to
/// `path` so; throws IoError naming the file.
void write_text_file(const std::string& path, std::string_view text);

/// Throws IoError naming `path` when it cannot be written (it tries, and leaves nothing behind).
void check_writable(const std::string& path);

/// Reads the whole of a regular file into `text`; false with the reason in `why` otherwise.
/// why: the type is checked on the open descriptor, opened without blocking, so that a FIFO or a
/// device named as an input neither blocks for ever nor is swapped in between a check and the
/// open (issue 13, F8).
bool read_regular_file(const std::string& path, std::string& text, std::string& why);

/// A file's path as results record it (results.json, summary.json): lexically normal ("./a/../b"
/// is "b") and, when it lies inside the current folder, relative to it; a path outside it is kept
/// as given. So results do not depend on how a path was spelled, and a path typed relative never
/// becomes an absolute path of this machine.
std::string recorded_path(const std::string& path);

/// True when `s` ends in `suffix`.
bool ends_with(std::string_view s, std::string_view suffix);

}  // namespace plumetrace
