#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>

namespace plumetrace {

/// The program version.
std::string_view version();

/// A file written whole or not at all: into `PATH.PID-N.part` (a name no other writer uses),
/// renamed over `PATH` by commit(); dropped when destroyed uncommitted (an error, an exception).
/// why: a reader, or a process killed while writing (a launcher ending a job), never sees half a
/// file, and two processes writing one file at once each finish theirs (issue 22, G19).
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

/// The largest input file read whole (scenario, preset, sweep, study files; 16 MiB): a thousand
/// times the largest the project ships. why: a file is read into memory and parsed before any
/// check of its content; a bound keeps a wrong file (a results store, a log) from taking the
/// machine's memory (issue 22, G7).
inline constexpr std::uint64_t kMaxInputBytes = 16ull << 20;

/// Reads the whole of a regular file of at most `max_bytes` into `text`; false with the reason in
/// `why` otherwise ("a folder, not a file", "not a regular file", "larger than ...", or the
/// system's). why: the type and size are checked on the open descriptor, opened without
/// blocking, so that a FIFO or a device named as an input neither blocks for ever nor is swapped
/// in between a check and the open (issue 13, F8). docs/reliability.md, "Inputs and outputs".
bool read_regular_file(const std::string& path, std::string& text, std::string& why,
                       std::uint64_t max_bytes = kMaxInputBytes);

/// The most characters of a name that becomes a folder under out/.
inline constexpr std::size_t kMaxFolderName = 100;

/// Whether a name read from a file (a sweep's, a study's) can be the folder of its outputs under
/// out/ as it is: letters, digits, '_', '-' and '.', not first, at most kMaxFolderName.
bool is_folder_name(std::string_view name);

/// "out/NAME" for a `name` read from `file`'s key `key`; throws ConfigError naming both when the
/// name is not a folder name. why: "../../etc/evil" must not lead out of out/ (issue 13, F12;
/// issue 22, G3).
std::string default_output_folder(const std::string& name, const std::string& file,
                                  const std::string& key = "name");

/// Makes the output folder `path` (and its parents) and, with `probe`, checks that a file can be
/// created in it; `what` names where the path came from in messages ("--out"). Throws
/// ConfigError when the path is empty or a file is in the way, IoError when the system refuses
/// (rights, a read-only or full disk, /proc). Without `probe` (the folder of a results store,
/// whose own checks name the store) only the folder is made.
void make_output_folder(const std::string& path, const std::string& what, bool probe = true);

/// The index of the first control character of `text` (U+0000-U+001F, U+007F, U+0080-U+009F in
/// UTF-8), or npos. why: a name or title is printed on terminals and written into CSV and HTML;
/// an escape sequence in it must not reach them (issue 22, G14).
std::size_t control_character(std::string_view text);

/// Throws ConfigError "WHERE: KEY: ..." when `text` holds a control character.
void check_printable(std::string_view text, const std::string& where, const std::string& key);

/// A file's path as results record it (results.json, summary.json): lexically normal ("./a/../b"
/// is "b") and, when it lies inside the current folder, relative to it; a path outside it is kept
/// as given. So results do not depend on how a path was spelled, and a path typed relative never
/// becomes an absolute path of this machine.
std::string recorded_path(const std::string& path);

/// True when `s` ends in `suffix`.
bool ends_with(std::string_view s, std::string_view suffix);

}  // namespace plumetrace
