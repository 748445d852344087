#include "plumetrace/experiment/store.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <stdexcept>
#include <string_view>
#include <thread>
#include <type_traits>
#include <vector>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/sim/result.hpp"

namespace plumetrace {

namespace {

// the schema this version writes: schema 1 plus a checksum of the runs and of the points in meta
// (schema 2), plus points numbered by the store, found by their values, and an epoch in meta that
// --fresh renews (schema 3), plus the robot's index in its team, `agent`, in the runs' key (schema
// 4); stores of schemas 1 to 3 are read as they are (their points are numbered in grid order,
// which is one numbering of schema 3; their runs are robot 0's) and upgraded when next written
constexpr std::string_view kSchemaVersion = "4";
constexpr std::string_view kLegacySchema = "1";
constexpr std::string_view kSchema2 = "2";
constexpr std::string_view kSchema3 = "3";
// the columns of table runs that a store of an older schema may lack: the agent (schema 4) and
// the result fields that came with it (which builds between 0.4.0 and schema 4 wrote under
// schema 3); read as agent 0 and NULL, and added when the store is next written
constexpr std::array<std::string_view, 4> kAddedColumns{"agent", "t_first_odor", "d_first_odor",
                                                        "declaration_error"};
// why: a merge holds the store for seconds; another process writing it waits that long
constexpr int kBusyTimeoutMs = 60000;

// whether an SQLite result code says the system failed (I/O), not the file's content
bool is_io_failure(int code) {
  switch (code & 0xff) {
    case SQLITE_IOERR:
    case SQLITE_FULL:
    case SQLITE_CANTOPEN:
    case SQLITE_READONLY:
    case SQLITE_PERM:
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
    case SQLITE_NOMEM:
    case SQLITE_NOLFS:
    case SQLITE_PROTOCOL:
    case SQLITE_AUTH:
      return true;
    default:
      return false;
  }
}

// an SQLite failure on the store at `path`, with its cause in words: StoreIoError when the
// system failed, StoreError when the file is at fault
[[noreturn]] void fail(sqlite3* db, int code, const std::string& path) {
  const int sys = sqlite3_system_errno(db);
  const std::string os = sys ? std::string(" (") + std::strerror(sys) + ")" : "";
  const std::string said = db ? sqlite3_errmsg(db) : sqlite3_errstr(code);
  std::string cause;
  switch (code & 0xff) {
    case SQLITE_FULL:
      cause = "write failed: the disk is full or the file size limit is reached" + os;
      break;
    case SQLITE_IOERR:
      if (code == SQLITE_IOERR_READ || code == SQLITE_IOERR_SHORT_READ) {
        cause = "read failed: " + said + os;
      } else if (sys == ENOSPC || sys == EFBIG || sys == EDQUOT) {
        cause = "write failed: the disk is full or the file size limit is reached" + os;
      } else {
        // why: SQLite does not always keep the errno of a failed write
        cause = "write failed: " + said +
                (sys ? os : " (a full disk, a file size limit or a failing device)");
      }
      break;
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      cause = "another process held the store locked for " + std::to_string(kBusyTimeoutMs / 1000) +
              " s (a long merge or a stuck process?)";
      break;
    case SQLITE_READONLY:
      cause = "cannot write it (a read-only file or folder): " + said;
      break;
    case SQLITE_CANTOPEN:
    case SQLITE_PERM:
      cause = "cannot open it" + os;
      break;
    case SQLITE_NOTADB:
      throw StoreError("'" + path +
                       "' is not a plumetrace results store (not an SQLite database, or its "
                       "header is damaged)");
    case SQLITE_CORRUPT:
      throw StoreError("results store '" + path + "' is damaged: " + said);
    default:
      cause = said;
  }
  const std::string message = "results store '" + path + "': " + cause;
  if (is_io_failure(code)) throw StoreIoError(message);
  throw StoreError(message);
}

// a store whose content cannot be trusted
[[noreturn]] void damaged(const std::string& path, const std::string& why) {
  throw StoreError("results store '" + path + "' is damaged: " + why);
}

// whether `text` is valid UTF-8
bool is_utf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = c < 0x80           ? 1
                          : (c >> 5) == 0x6  ? 2
                          : (c >> 4) == 0xe  ? 3
                          : (c >> 3) == 0x1e ? 4
                                             : 0;
    if (n == 0 || i + n > text.size()) return false;
    for (std::size_t k = 1; k < n; ++k) {
      if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) return false;
    }
    i += n;
  }
  return true;
}

// a value read from a store, for a message: at most 40 bytes, control bytes (and the bytes of
// text that is not UTF-8) as \xHH
std::string shown(std::string_view text) {
  const bool utf8 = is_utf8(text);
  std::string out;
  for (const char ch : text.substr(0, 40)) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f || (c >= 0x80 && !utf8)) {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else {
      out += ch;
    }
  }
  return text.size() > 40 ? out + "..." : out;
}

// a prepared statement, finalized on scope exit
class Statement {
 public:
  Statement(sqlite3* db, const char* sql, const std::string& path) : db_(db), path_(path) {
    const int rc = sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr);
    if (rc != SQLITE_OK) fail(db_, rc, path_);
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // the index of the parameter `name` (":time_s"); a name the statement lacks is a bug
  int parameter(const char* name) const {
    const int i = sqlite3_bind_parameter_index(stmt_, name);
    if (i == 0) throw std::logic_error(std::string("SQL statement has no parameter ") + name);
    return i;
  }
  // the names of the result columns, in order
  std::vector<std::string> column_names() const {
    std::vector<std::string> names;
    for (int i = 0; i < sqlite3_column_count(stmt_); ++i) {
      names.emplace_back(sqlite3_column_name(stmt_, i));
    }
    return names;
  }
  // the index of the result column `name`; a name the statement lacks is a bug
  int column(std::string_view name) const {
    for (int i = 0; i < sqlite3_column_count(stmt_); ++i) {
      if (name == sqlite3_column_name(stmt_, i)) return i;
    }
    throw std::logic_error("SQL statement has no column " + std::string(name));
  }
  template <class T>
  void bind(const char* name, const T& v) {
    bind(parameter(name), v);
  }
  void bind(int i, std::string_view v) {
    // why: an empty view may have no data, which SQLite would bind as NULL
    sqlite3_bind_text(stmt_, i, v.empty() ? "" : v.data(), static_cast<int>(v.size()),
                      SQLITE_TRANSIENT);
  }
  void bind(int i, std::int64_t v) { sqlite3_bind_int64(stmt_, i, v); }
  void bind(int i, double v) {
    if (std::isnan(v)) {
      sqlite3_bind_null(stmt_, i);
    } else {
      sqlite3_bind_double(stmt_, i, v);
    }
  }
  // true while rows come
  bool step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) fail(db_, rc, path_);
    return false;
  }
  void reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  int type(int col) const { return sqlite3_column_type(stmt_, col); }
  std::string text(std::string_view name) const { return text(column(name)); }
  std::int64_t integer(std::string_view name) const { return integer(column(name)); }
  std::string text(int col) const {
    const auto* p = sqlite3_column_text(stmt_, col);
    return p ? std::string(reinterpret_cast<const char*>(p),
                           static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
             : "";
  }
  std::int64_t integer(int col) const { return sqlite3_column_int64(stmt_, col); }
  double real(int col) const {
    return sqlite3_column_type(stmt_, col) == SQLITE_NULL ? NAN : sqlite3_column_double(stmt_, col);
  }

 private:
  sqlite3* db_;
  std::string path_;
  sqlite3_stmt* stmt_ = nullptr;
};

void exec_sql(sqlite3* db, const std::string& path, const std::string& sql) {
  char* err = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err);
  sqlite3_free(err);
  if (rc != SQLITE_OK) fail(db, rc, path);
}

// the SQL type of a key member's or a result field's value: a name as text, an outcome by its
// name, a flag as 0 or 1
template <class T>
constexpr std::string_view sql_type() {
  if constexpr (std::is_same_v<T, Outcome> || std::is_same_v<T, std::string>) {
    return "TEXT";
  } else if constexpr (std::is_floating_point_v<T>) {
    return "REAL";
  } else {
    static_assert(std::is_integral_v<T>, "a stored integer is an integer or a flag");
    return "INTEGER";
  }
}

// the columns of table runs and their declarations: the run key (RunRow::key_fields), the seed
// (TEXT keeps the full unsigned 64-bit seed) and the point's config_hash, then RunResult::fields
const std::vector<std::pair<std::string, std::string>>& run_columns() {
  static const auto columns = [] {
    std::vector<std::pair<std::string, std::string>> c;
    RunRow::key_fields(RunRow{}, [&](std::string_view name, const auto& value) {
      c.emplace_back(name,
                     std::string(sql_type<std::remove_cvref_t<decltype(value)>>()) + " NOT NULL");
    });
    c.emplace_back("seed", "TEXT NOT NULL");
    c.emplace_back("config_hash", "TEXT NOT NULL");
    const RunResult r{};
    RunResult::fields(r, [&](const ResultField& f, const auto& value) {
      const std::string_view type = sql_type<std::remove_cvref_t<decltype(value)>>();
      c.emplace_back(f.name, std::string(type) + (f.nullable ? "" : " NOT NULL"));
    });
    return c;
  }();
  return columns;
}

// the names of table runs' columns, comma-separated, each after `prefix` (":" for parameters)
std::string run_column_list(std::string_view prefix) {
  std::string list;
  for (const auto& [name, decl] : run_columns()) {
    list += (list.empty() ? "" : ", ") + std::string(prefix) + name;
  }
  return list;
}

// the run key's column names, comma-separated (a primary key, an ORDER BY)
std::string run_key_list() {
  std::string list;
  for (const std::string_view name : kRunKeyFields) {
    list += (list.empty() ? "" : ", ") + std::string(name);
  }
  return list;
}

// the tables of a store, made when it is new
const std::string& schema_sql() {
  static const std::string sql = [] {
    std::string runs;
    for (const auto& [name, decl] : run_columns()) runs += "  " + name + " " + decl + ",\n";
    return R"sql(
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS points (
  sweep TEXT NOT NULL, point INTEGER NOT NULL, axis_values TEXT NOT NULL,
  config_hash TEXT NOT NULL, config TEXT NOT NULL,
  PRIMARY KEY (sweep, point));
CREATE TABLE IF NOT EXISTS runs (
)sql" + runs +
           "  PRIMARY KEY (" + run_key_list() + "));\n";
  }();
  return sql;
}

// the columns of each table of schema_sql(), in order
const std::map<std::string, std::vector<std::string>>& schema_columns() {
  static const std::map<std::string, std::vector<std::string>> columns = [] {
    std::vector<std::string> runs;
    for (const auto& [name, decl] : run_columns()) runs.push_back(name);
    return std::map<std::string, std::vector<std::string>>{
        {"meta", {"key", "value"}},
        {"points", {"sweep", "point", "axis_values", "config_hash", "config"}},
        {"runs", runs}};
  }();
  return columns;
}

sqlite3* open_db(const std::string& name, const std::string& path, int flags) {
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(name.c_str(), &db, flags, nullptr);
  if (rc != SQLITE_OK) {
    if (!db) throw StoreIoError("cannot open results store '" + path + "': out of memory");
    try {
      fail(db, rc, path);
    } catch (...) {
      sqlite3_close(db);
      throw;
    }
  }
  sqlite3_extended_result_codes(db, 1);
  sqlite3_busy_timeout(db, kBusyTimeoutMs);
  return db;
}

// "file:" URI of a path, for URI parameters
std::string file_uri(const std::string& path) {
  std::string uri = "file:";
  for (const char c : std::filesystem::absolute(path).string()) {
    if (c == '%' || c == '?' || c == '#') {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", static_cast<unsigned char>(c));
      uri += hex;
    } else {
      uri += c;
    }
  }
  return uri;
}

// whether the store has a write-ahead log with content (runs not yet in the file itself)
bool has_journal(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path + "-wal", ec);
  return !ec && size > 0;
}

// a transaction that reads one snapshot of the store, ended on scope exit
class ReadTransaction {
 public:
  ReadTransaction(sqlite3* db, const std::string& path) : db_(db) {
    exec_sql(db, path, "BEGIN;");
    // why: the snapshot starts at the first read; take it now, so that failures show here
    Statement(db, "SELECT count(*) FROM sqlite_master", path).step();
  }
  ~ReadTransaction() { sqlite3_exec(db_, "COMMIT;", nullptr, nullptr, nullptr); }
  ReadTransaction(const ReadTransaction&) = delete;
  ReadTransaction& operator=(const ReadTransaction&) = delete;

 private:
  sqlite3* db_;
};

// an existing store opened read-only, closed on scope exit; a store in a folder this user cannot
// write (where SQLite cannot make its shared-memory file) is opened as immutable when no journal
// holds runs that are not yet in the file
class ReadOnlyStore {
 public:
  explicit ReadOnlyStore(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) {
      throw StoreError("cannot open results store '" + path + "': no such file");
    }
    db_ = open_db(path, path, SQLITE_OPEN_READONLY);
    try {
      ReadTransaction probe(db_, path);
    } catch (const StoreIoError& e) {
      sqlite3_close(db_);
      db_ = nullptr;
      if (has_journal(path)) {
        throw StoreIoError(std::string(e.what()) + "; its journal '" + path +
                           "-wal' holds runs not yet in the file, which SQLite cannot read "
                           "without writing next to it: run this once as a user who may write "
                           "the folder, or copy the store with its -wal file");
      }
      db_ = open_db(file_uri(path) + "?immutable=1", path, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI);
    } catch (...) {
      sqlite3_close(db_);
      throw;
    }
  }
  ~ReadOnlyStore() { sqlite3_close(db_); }
  ReadOnlyStore(const ReadOnlyStore&) = delete;
  ReadOnlyStore& operator=(const ReadOnlyStore&) = delete;

  sqlite3* db() const { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

// refuses a file whose size does not fit its pages, as an interrupted copy leaves it (SQLite
// reads the missing bytes as zeros); called inside a read transaction, so that the page count is
// that of the snapshot read
void check_size(sqlite3* db, const std::string& path) {
  Statement size_q(db, "PRAGMA page_size", path);
  Statement count_q(db, "PRAGMA page_count", path);
  const std::int64_t page_size = size_q.step() ? size_q.integer("page_size") : 0;
  const std::int64_t pages = count_q.step() ? count_q.integer("page_count") : 0;
  std::error_code ec;
  const auto bytes = static_cast<std::int64_t>(std::filesystem::file_size(path, ec));
  if (ec) throw StoreIoError("results store '" + path + "': cannot read its size: " + ec.message());
  const std::string size_text = "the file has " + std::to_string(bytes) + " bytes, ";
  if (page_size <= 0 || bytes % page_size != 0) {
    damaged(path, size_text + "not a whole number of its " + std::to_string(page_size) +
                      "-byte pages (truncated, e.g. by an interrupted copy?)");
  }
  // why: with a journal, pages may be in the journal and not yet in the file
  if (!has_journal(path) && bytes != pages * page_size) {
    damaged(path, size_text + "its " + std::to_string(pages) + " pages need " +
                      std::to_string(pages * page_size) +
                      " (truncated, e.g. by an interrupted copy?)");
  }
}

// the columns of a table, in order
std::vector<std::string> table_columns(sqlite3* db, const std::string& path,
                                       const std::string& table) {
  std::string quoted;
  for (const char c : table) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  Statement q(db, ("PRAGMA table_info(\"" + quoted + "\")").c_str(), path);
  std::vector<std::string> columns;
  while (q.step()) columns.push_back(q.text("name"));
  return columns;
}

bool is_added_column(std::string_view name) {
  return std::find(kAddedColumns.begin(), kAddedColumns.end(), name) != kAddedColumns.end();
}

// whether `columns` are those of table runs as a store of an older schema has them: this
// schema's with some of kAddedColumns left out, the others in order
bool is_older_runs_table(const std::vector<std::string>& columns) {
  std::vector<std::string> kept;
  for (const auto& name : schema_columns().at("runs")) {
    if (!is_added_column(name) ||
        std::find(columns.begin(), columns.end(), name) != columns.end()) {
      kept.push_back(name);
    }
  }
  return kept == columns;
}

enum class Layout {
  kEmpty,       // no tables, or plumetrace's tables without a row
  kPlumetrace,  // plumetrace's tables
  kForeign,     // anything else
};

// what the database holds, read inside a transaction; `found` lists a foreign one's tables
Layout layout_of(sqlite3* db, const std::string& path, std::string* found = nullptr) {
  const auto& columns = schema_columns();
  std::map<std::string, std::vector<std::string>> tables;
  bool foreign = false;
  {
    Statement q(db, "SELECT type, name FROM sqlite_master", path);
    while (q.step()) {
      const std::string type = q.text("type"), name = q.text("name");
      if (type == "table") {
        tables[name];
        foreign = foreign || !columns.count(name);
      } else {
        foreign = foreign || type != "index" || name.rfind("sqlite_autoindex_", 0) != 0;
      }
    }
  }
  if (tables.empty() && !foreign) return Layout::kEmpty;
  for (auto& [name, cols] : tables) {
    cols = table_columns(db, path, name);
    const auto it = columns.find(name);
    foreign = foreign || it == columns.end() ||
              (it->second != cols && !(name == "runs" && is_older_runs_table(cols)));
  }
  foreign = foreign || tables.size() != columns.size();
  if (foreign) {
    if (found) {
      for (const auto& [name, cols] : tables) {
        std::string list;
        for (const auto& c : cols) list += (list.empty() ? "" : ", ") + c;
        *found += (found->empty() ? "" : ", ") + shown(name) + "(" + shown(list) + ")";
      }
      if (found->empty()) *found = "views, triggers or indexes";
    }
    return Layout::kForeign;
  }
  for (const auto& [name, cols] : tables) {
    Statement q(db, ("SELECT 1 FROM " + name + " LIMIT 1").c_str(), path);
    if (q.step()) return Layout::kPlumetrace;
  }
  return Layout::kEmpty;
}

[[noreturn]] void not_a_store(const std::string& path, const std::string& found) {
  throw StoreError("'" + path + "' is not a plumetrace results store (it holds " + found +
                   "); plumetrace leaves it unchanged: choose another --store");
}

// a whole number in [lo, hi], or nothing
std::optional<std::int64_t> whole_number(const std::string& text, std::int64_t lo,
                                         std::int64_t hi) {
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || v < lo || v > hi) {
    return std::nullopt;
  }
  return v;
}

// -0 as 0 and every NaN as one: SQLite keeps neither -0 (stored as the integer 0) nor a NaN's
// bits (stored as NULL)
double canonical(double v) {
  if (v == 0.0) return 0.0;
  if (std::isnan(v)) return std::numeric_limits<double>::quiet_NaN();
  return v;
}

// a 64-bit hash of a row's fields (FNV-1a, length-prefixed fields, then a final mix), so that the
// sum of a table's row hashes changes with any change, loss or addition of a row
class RowHash {
 public:
  RowHash& add(std::string_view s) {
    add(static_cast<std::uint64_t>(s.size()));
    for (const char c : s) byte(static_cast<unsigned char>(c));
    return *this;
  }
  RowHash& add(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) byte(static_cast<unsigned char>(v >> (8 * i)));
    return *this;
  }
  RowHash& add(std::int64_t v) { return add(static_cast<std::uint64_t>(v)); }
  RowHash& add(double v) { return add(std::bit_cast<std::uint64_t>(canonical(v))); }
  std::uint64_t value() const {
    std::uint64_t z = h_ + 0x9e3779b97f4a7c15ULL;  // splitmix64's finalizer
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  void byte(unsigned char c) { h_ = (h_ ^ c) * 0x100000001b3ULL; }
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

// the number of result fields a store keeps: all but the derived ones
constexpr std::size_t kStoredFields = [] {
  std::size_t n = 0;
  const RunResult r{};
  RunResult::fields(r, [&](const ResultField&, auto&& value) {
    if constexpr (!kDerivedField<decltype(value)>) ++n;
  });
  return n;
}();

// a run's stored result fields as 64 bits each, as the store keeps them (-0 is 0, NaN is NULL)
std::array<std::uint64_t, kStoredFields> stored_bits(const RunResult& m) {
  std::array<std::uint64_t, kStoredFields> bits{};
  std::size_t k = 0;
  RunResult::fields(m, [&](const ResultField&, auto&& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (kDerivedField<decltype(value)>) {
      return;
    } else if constexpr (std::is_floating_point_v<T>) {
      bits[k++] = std::bit_cast<std::uint64_t>(canonical(value));
    } else {
      bits[k++] = static_cast<std::uint64_t>(value);
    }
  });
  return bits;
}

// where the columns of table runs are in a statement, found by their names: its parameters
// (":time_s") in an INSERT, or its result columns in a SELECT; -1 for a column that the table of
// a store of an older schema lacks (one of kAddedColumns)
struct RunColumnsAt {
  std::array<int, kRunKeyFields.size()> key{};  // in kRunKeyFields order
  int seed = 0, config_hash = 0;
  std::vector<int> fields;  // one per result field, in RunResult::fields order
  int rowid = 0;            // in a SELECT
};

// every column of this schema's table runs (for what depends only on which columns there are)
const RunColumnsAt& every_run_column() {
  static const RunColumnsAt at{.key = {}, .fields = std::vector<int>(kResultFields.size(), 0)};
  return at;
}

// a run's hash over the columns its table has (`at`): a store's checksum covers what it holds,
// so that the checksums of an older schema stay those it wrote
std::uint64_t hash_of(const RunRow& r, const RunColumnsAt& at = every_run_column()) {
  RowHash h;
  std::size_t k = 0;
  RunRow::key_fields(r, [&](std::string_view, const auto& value) {
    if (at.key[k++] < 0) return;
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(value)>, std::string>) {
      h.add(value);
    } else {
      h.add(static_cast<std::int64_t>(value));
    }
  });
  h.add(r.result.seed).add(r.config_hash);
  k = 0;
  RunResult::fields(r.result, [&](const ResultField&, auto&& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    if (at.fields[k++] < 0) return;
    if constexpr (kDerivedField<decltype(value)>) {
      return;
    } else if constexpr (std::is_same_v<T, Outcome>) {
      h.add(outcome_name(value));
    } else if constexpr (std::is_floating_point_v<T>) {
      h.add(static_cast<double>(value));
    } else {
      h.add(static_cast<std::int64_t>(value));
    }
  });
  return h.value();
}

std::uint64_t hash_of(const StoredPoint& p) {
  return RowHash()
      .add(p.sweep)
      .add(static_cast<std::int64_t>(p.point))
      .add(p.axis_values)
      .add(p.config_hash)
      .add(p.config)
      .value();
}

// a table's checksum: how many rows and the sum of their hashes (meta "check:runs",
// "check:points": "COUNT HEX")
struct Checksum {
  std::int64_t count = 0;
  std::uint64_t sum = 0;

  void add(std::uint64_t hash) {
    ++count;
    sum += hash;
  }
  bool operator==(const Checksum&) const = default;
  std::string text() const {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(sum));
    return std::to_string(count) + " " + hex;
  }
};

std::optional<Checksum> parse_checksum(const std::string& text) {
  const auto space = text.find(' ');
  if (space == std::string::npos || text.size() - space - 1 != 16) return std::nullopt;
  const auto count = whole_number(text.substr(0, space), 0, std::numeric_limits<int64_t>::max());
  Checksum c;
  const char* hex = text.data() + space + 1;
  const auto [ptr, ec] = std::from_chars(hex, hex + 16, c.sum, 16);
  if (!count || ec != std::errc() || ptr != hex + 16) return std::nullopt;
  c.count = *count;
  return c;
}

// "sweep NAME, point P, trial T, agent A"
std::string key_text(const RunRow& r) {
  std::string text;
  RunRow::key_fields(r, [&](std::string_view name, const auto& value) {
    text += (text.empty() ? "" : ", ") + std::string(name) + " ";
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(value)>, std::string>) {
      text += shown(value);
    } else {
      text += std::to_string(value);
    }
  });
  return text;
}

const char* type_name(int type) {
  switch (type) {
    case SQLITE_INTEGER:
      return "an integer";
    case SQLITE_FLOAT:
      return "a real number";
    case SQLITE_TEXT:
      return "text";
    case SQLITE_BLOB:
      return "a blob";
    default:
      return "NULL";
  }
}

// reads the typed columns of one row of a table, naming the store, the row and the column of a
// value that is not what the column holds
class RowReader {
 public:
  RowReader(const Statement& q, const std::string& path, std::string row)
      : q_(q), path_(path), row_(std::move(row)) {}

  void name(std::string row) { row_ = std::move(row); }
  [[noreturn]] void bad(int col, std::string_view column, const std::string& why) const {
    damaged(path_, row_ + ": column " + std::string(column) + " holds " + type_name(q_.type(col)) +
                       (q_.type(col) == SQLITE_NULL ? "" : " '" + shown(q_.text(col)) + "'") +
                       ", " + why);
  }
  std::string text(int col, std::string_view column) const {
    if (q_.type(col) != SQLITE_TEXT) bad(col, column, "not text");
    return q_.text(col);
  }
  std::int64_t integer(int col, std::string_view column, std::int64_t lo, std::int64_t hi) const {
    if (q_.type(col) != SQLITE_INTEGER || q_.integer(col) < lo || q_.integer(col) > hi) {
      bad(col, column,
          "not a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
    }
    return q_.integer(col);
  }
  double real(int col, std::string_view column, bool nullable) const {
    const int type = q_.type(col);
    if (type != SQLITE_FLOAT && !(nullable && type == SQLITE_NULL)) {
      bad(col, column, nullable ? "not a number or NULL" : "not a number");
    }
    return q_.real(col);
  }

 private:
  const Statement& q_;
  const std::string& path_;
  std::string row_;
};

template <class Find>
RunColumnsAt locate_run_columns(Find find) {
  RunColumnsAt at;
  for (std::size_t k = 0; k < kRunKeyFields.size(); ++k) at.key[k] = find(kRunKeyFields[k]);
  at.seed = find("seed");
  at.config_hash = find("config_hash");
  for (const ResultField& f : kResultFields) at.fields.push_back(find(f.name));
  return at;
}

// the parameters of an INSERT into table runs
RunColumnsAt run_parameters(const Statement& put) {
  return locate_run_columns(
      [&](std::string_view name) { return put.parameter((":" + std::string(name)).c_str()); });
}

// the result columns of a SELECT of every column of table runs and the rowid (-1 for a column
// of kAddedColumns that the table lacks)
RunColumnsAt run_columns_of(const Statement& q) {
  // why: SQLite locks the connection for each column name; they are read once
  const std::vector<std::string> names = q.column_names();
  const auto find = [&](std::string_view name) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end() && is_added_column(name)) return -1;
    if (it == names.end()) {
      throw std::logic_error("SQL statement has no column " + std::string(name));
    }
    return static_cast<int>(it - names.begin());
  };
  RunColumnsAt at = locate_run_columns(find);
  at.rowid = find("rowid");
  return at;
}

// a SELECT of every column of table runs and the rowid, before its WHERE or ORDER BY; why: *,
// as the columns are read by their names (run_columns_of), and a shorter text is parsed faster
constexpr const char* kSelectRuns = "SELECT *, rowid FROM runs";

// an INSERT of a run with a named parameter for each column
const std::string& insert_run() {
  static const std::string sql =
      "INSERT INTO runs (" + run_column_list("") + ") VALUES (" + run_column_list(":") + ")";
  return sql;
}

// the run at the statement's cursor, every value checked
RunRow row_at(const Statement& q, const RunColumnsAt& at, const std::string& path) {
  RowReader in(q, path, "row " + std::to_string(q.integer(at.rowid)) + " of table runs");
  RunRow r;
  std::size_t key = 0;
  RunRow::key_fields(r, [&](std::string_view name, auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const int col = at.key[key++];
    if (col < 0) return;  // a store of an older schema: robot 0
    if constexpr (std::is_same_v<T, std::string>) {
      value = in.text(col, name);
    } else {
      constexpr auto most = static_cast<std::int64_t>(
          std::min<std::uint64_t>(std::numeric_limits<T>::max(), INT64_MAX));
      value = static_cast<T>(in.integer(col, name, 0, most));
    }
  });
  in.name("run (" + key_text(r) + ")");
  r.config_hash = in.text(at.config_hash, "config_hash");
  RunResult& m = r.result;
  const std::string seed = in.text(at.seed, "seed");
  const auto [ptr, ec] = std::from_chars(seed.data(), seed.data() + seed.size(), m.seed);
  if (seed.empty() || ec != std::errc() || ptr != seed.data() + seed.size()) {
    in.bad(at.seed, "seed", "not a whole number from 0 to 18446744073709551615");
  }
  m.trial = r.trial;
  m.agent = r.agent;
  std::size_t k = 0;
  RunResult::fields(m, [&](const ResultField& f, auto&& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const int col = at.fields[k++];
    if (col < 0) return;  // a store of an older schema: NaN, as a nullable field of no value
    if constexpr (kDerivedField<decltype(value)>) {
      static_assert(std::is_same_v<T, bool>, "a derived field is a flag");
      if (in.integer(col, f.name, 0, 1) != (value ? 1 : 0)) {
        in.bad(col, f.name, "which contradicts the columns before it");
      }
    } else if constexpr (std::is_same_v<T, Outcome>) {
      try {
        value = parse_outcome(in.text(col, f.name));
      } catch (const ConfigError&) {
        value = Outcome::kRunning;
      }
      // why: a stored run has ended
      if (value == Outcome::kRunning) {
        std::string names;
        for (const std::string_view name : kOutcomeNames) {
          if (name != outcome_name(Outcome::kRunning)) {
            names += (names.empty() ? "" : ", ") + std::string(name);
          }
        }
        in.bad(col, f.name, "not one of " + names);
      }
    } else if constexpr (std::is_floating_point_v<T>) {
      value = in.real(col, f.name, f.nullable);
    } else {
      value = static_cast<T>(in.integer(col, f.name, 0, std::numeric_limits<T>::max()));
    }
  });
  return r;
}

// binds the members of a run's key to the parameters at `key` (in kRunKeyFields order)
void bind_key(Statement& put, const std::array<int, kRunKeyFields.size()>& key, const RunRow& r) {
  std::size_t k = 0;
  RunRow::key_fields(r, [&](std::string_view, const auto& value) {
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(value)>, std::string>) {
      put.bind(key[k++], std::string_view(value));
    } else {
      put.bind(key[k++], static_cast<std::int64_t>(value));
    }
  });
}

// binds a run to the parameters of insert_run(), found at `at`
void bind_run(Statement& put, const RunColumnsAt& at, const RunRow& r) {
  bind_key(put, at.key, r);
  put.bind(at.seed, std::to_string(r.result.seed));
  put.bind(at.config_hash, r.config_hash);
  std::size_t k = 0;
  RunResult::fields(r.result, [&](const ResultField&, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const int i = at.fields[k++];
    if constexpr (std::is_same_v<T, Outcome>) {
      put.bind(i, outcome_name(value));
    } else if constexpr (std::is_floating_point_v<T>) {
      put.bind(i, static_cast<double>(value));
    } else {
      put.bind(i, static_cast<std::int64_t>(value));
    }
  });
}

// the same values in every stored column, as the store keeps them (-0 is 0, NaN is NULL)
bool same_run(const RunRow& a, const RunRow& b) {
  return a.config_hash == b.config_hash && a.result.seed == b.result.seed &&
         stored_bits(a.result) == stored_bits(b.result);
}

std::string meta_value(sqlite3* db, const std::string& path, const std::string& key) {
  Statement q(db, "SELECT value FROM meta WHERE key = :key", path);
  q.bind(":key", key);
  return q.step() ? q.text("value") : "";
}

// the runs per point recorded under meta key `key` ("runs:NAME")
int runs_value(const std::string& path, const std::string& key, const std::string& text) {
  const auto v = whole_number(text, 0, INT_MAX);
  if (!v) {
    damaged(path, "meta key '" + shown(key) + "' holds '" + shown(text) +
                      "', not a whole number of runs");
  }
  return static_cast<int>(*v);
}

// the --set texts recorded under meta key `key` ("sets:NAME"): a JSON list of strings
std::vector<std::string> sets_value(const std::string& path, const std::string& key,
                                    const std::string& text) {
  const auto doc = nlohmann::json::parse(text, nullptr, false);
  std::vector<std::string> sets;
  if (doc.is_array()) {
    for (const auto& s : doc) {
      if (!s.is_string()) break;
      sets.push_back(s.get<std::string>());
    }
  }
  if (!doc.is_array() || sets.size() != doc.size()) {
    damaged(path, "meta key '" + shown(key) + "' holds '" + shown(text) +
                      "', not a JSON list of --set texts");
  }
  return sets;
}

// the meta rows, checked; `checks` gets the checksums (none in a store of schema 1)
std::map<std::string, std::string> read_meta(sqlite3* db, const std::string& path,
                                             std::optional<Checksum> checks[2]) {
  std::map<std::string, std::string> meta;
  {
    Statement q(db, "SELECT key, value, rowid FROM meta", path);
    const int key_at = q.column("key"), value_at = q.column("value"), rowid = q.column("rowid");
    while (q.step()) {
      const RowReader in(q, path, "row " + std::to_string(q.integer(rowid)) + " of table meta");
      const std::string key = in.text(key_at, "key");
      meta[key] = in.text(value_at, "value");
    }
  }
  const auto need = [&](const std::string& key) -> const std::string& {
    if (meta[key].empty()) damaged(path, "it has no '" + key + "' in its meta table");
    return meta[key];
  };
  const std::string& schema = need("schema");
  if (schema != kSchemaVersion && schema != kSchema3 && schema != kSchema2 &&
      schema != kLegacySchema) {
    damaged(path, "its schema is '" + shown(schema) + "'; this plumetrace reads schema " +
                      std::string(kSchemaVersion) + " (and " + std::string(kSchema3) + ", " +
                      std::string(kSchema2) + ", " + std::string(kLegacySchema) + ")");
  }
  if (!nlohmann::json::accept(need("definition"))) {
    damaged(path, "its definition (meta key 'definition') is not JSON");
  }
  need("version");
  for (const auto& [key, value] : meta) {
    if (key.rfind("runs:", 0) == 0) runs_value(path, key, value);
    if (key.rfind("sets:", 0) == 0) sets_value(path, key, value);
  }
  if (meta.count("shard")) {
    int i = 0, n = 0;
    char extra = 0;
    if (std::sscanf(meta["shard"].c_str(), "%d/%d%c", &i, &n, &extra) != 2 || i < 1 || n < 1 ||
        i > n) {
      damaged(path,
              "meta key 'shard' holds '" + shown(meta["shard"]) + "', not i/n with 1 <= i <= n");
    }
  }
  const char* keys[2] = {"check:runs", "check:points"};
  for (int t = 0; t < 2; ++t) {
    checks[t].reset();
    if (schema == kLegacySchema && !meta.count(keys[t])) continue;
    checks[t] = parse_checksum(need(keys[t]));
    if (!checks[t]) {
      damaged(path, "meta key '" + std::string(keys[t]) + "' holds '" + shown(meta[keys[t]]) +
                        "', not a checksum (COUNT HEX)");
    }
  }
  return meta;
}

// reads and checks everything a store holds (inside a read transaction): the file's size, its
// tables, every value, each run against its point, and the checksums
StoreContents load(sqlite3* db, const std::string& path) {
  check_size(db, path);
  std::string found;
  switch (layout_of(db, path, &found)) {
    case Layout::kEmpty:
      throw StoreError("'" + path + "' is not a plumetrace results store (it is empty)");
    case Layout::kForeign:
      not_a_store(path, found);
    case Layout::kPlumetrace:
      break;
  }
  std::optional<Checksum> checks[2];
  const auto meta = read_meta(db, path, checks);
  StoreContents c;
  c.info.definition = meta.at("definition");
  c.info.version = meta.at("version");
  c.info.shard = meta.count("shard") ? meta.at("shard") : "";

  // the points
  Checksum points_sum;
  std::map<std::pair<std::string, int>, std::string> hash_of_point;
  {
    Statement q(db,
                "SELECT sweep, point, axis_values, config_hash, config, rowid FROM points "
                "ORDER BY sweep, point",
                path);
    const int sweep = q.column("sweep"), point = q.column("point"),
              axis_values = q.column("axis_values"), config_hash = q.column("config_hash"),
              config = q.column("config"), rowid = q.column("rowid");
    while (q.step()) {
      const RowReader in(q, path, "row " + std::to_string(q.integer(rowid)) + " of table points");
      StoredPoint p;
      p.sweep = in.text(sweep, "sweep");
      p.point = static_cast<int>(in.integer(point, "point", 0, INT_MAX));
      p.axis_values = in.text(axis_values, "axis_values");
      p.config_hash = in.text(config_hash, "config_hash");
      p.config = in.text(config, "config");
      if (!hash_of_point.emplace(std::pair{p.sweep, p.point}, p.config_hash).second) {
        damaged(path, "it holds sweep " + shown(p.sweep) + ", point " + std::to_string(p.point) +
                          " twice in table points");
      }
      points_sum.add(hash_of(p));
      ++c.info.points[p.sweep];
      c.points.push_back(std::move(p));
    }
  }

  // the runs, each against its point, in the order of their key (of the key columns a store of
  // an older schema has: its runs are robot 0's)
  Checksum runs_sum;
  {
    const std::vector<std::string> held = table_columns(db, path, "runs");
    std::string order;
    for (const std::string_view name : kRunKeyFields) {
      if (std::find(held.begin(), held.end(), name) == held.end()) continue;
      order += (order.empty() ? " ORDER BY " : ", ") + std::string(name);
    }
    Statement q(db, (std::string(kSelectRuns) + order).c_str(), path);
    const RunColumnsAt at = run_columns_of(q);
    while (q.step()) {
      RunRow r = row_at(q, at, path);
      if (!c.rows.empty() && RunRow::key_of(c.rows.back()) >= RunRow::key_of(r)) {
        damaged(path, "it holds run (" + key_text(r) + ") twice or out of order");
      }
      const auto point = hash_of_point.find({r.sweep, r.point});
      if (point == hash_of_point.end()) {
        damaged(path, "run (" + key_text(r) + ") has no point in table points");
      }
      if (point->second != r.config_hash) {
        damaged(path, "run (" + key_text(r) + "): column config_hash holds '" +
                          shown(r.config_hash) + "', but its point's is '" + shown(point->second) +
                          "'");
      }
      runs_sum.add(hash_of(r, at));
      c.rows.push_back(std::move(r));
    }
  }
  const auto compare = [&](const std::optional<Checksum>& want, const Checksum& got,
                           const std::string& table) {
    if (!want || *want == got) return;
    if (want->count != got.count) {
      damaged(path, "table " + table + " holds " + std::to_string(got.count) +
                        " rows, its checksum says " + std::to_string(want->count) +
                        " (rows lost or added outside plumetrace)");
    }
    damaged(path, "the values in table " + table +
                      " do not match their checksum (changed outside plumetrace: a damaged "
                      "file or an edit)");
  };
  compare(checks[0], runs_sum, "runs");
  compare(checks[1], points_sum, "points");

  for (const auto& [key, value] : meta) {
    if (key.rfind("sets:", 0) == 0) c.info.sets[key.substr(5)] = sets_value(path, key, value);
  }
  // the runs per point asked of each sweep, and how many of those are stored
  for (const auto& [sweep, count] : c.info.points) {
    const auto it = meta.find("runs:" + sweep);
    int runs = 0;
    if (it != meta.end()) {
      runs = runs_value(path, it->first, it->second);
    } else {
      // a store from before runs were recorded: as many as its largest trial says
      for (const auto& r : c.rows) {
        if (r.sweep == sweep) runs = std::max(runs, static_cast<int>(r.trial + 1));
      }
    }
    c.info.runs[sweep] = runs;
    c.info.stored[sweep] = 0;
  }
  // a trial counts once, whatever its team's size (the rows are in key order: a team's together)
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    const RunRow& r = c.rows[i];
    if (i > 0 && std::tie(r.sweep, r.point, r.trial) ==
                     std::tie(c.rows[i - 1].sweep, c.rows[i - 1].point, c.rows[i - 1].trial)) {
      continue;
    }
    const auto it = c.info.runs.find(r.sweep);
    if (it != c.info.runs.end() && r.trial < static_cast<std::uint64_t>(it->second)) {
      ++c.info.stored[r.sweep];
    }
  }
  return c;
}

// makes table runs of a store of an older schema anew with this schema's columns, inside the
// caller's transaction: the columns it lacks hold 0 where they may not be NULL (agent: each run
// is a robot alone's), else NULL
void add_missing_columns(sqlite3* db, const std::string& path) {
  const std::vector<std::string> held = table_columns(db, path, "runs");
  std::string into, from;
  for (const auto& [name, decl] : run_columns()) {
    const bool has = std::find(held.begin(), held.end(), name) != held.end();
    const bool not_null = decl.find("NOT NULL") != std::string::npos;
    if (!has && !not_null) continue;
    into += (into.empty() ? "" : ", ") + name;
    from += (from.empty() ? "" : ", ") + (has ? name : std::string("0"));
  }
  exec_sql(db, path,
           "ALTER TABLE runs RENAME TO runs_of_older_schema;" + schema_sql() +
               "INSERT INTO runs (" + into + ") SELECT " + from +
               " FROM runs_of_older_schema; DROP TABLE runs_of_older_schema;");
}

// the checksums of what a store holds
std::pair<Checksum, Checksum> checksums_of(const StoreContents& c) {
  std::pair<Checksum, Checksum> sums;
  for (const auto& r : c.rows) sums.first.add(hash_of(r));
  for (const auto& p : c.points) sums.second.add(hash_of(p));
  return sums;
}

void put_meta(sqlite3* db, const std::string& path, const std::string& key,
              const std::string& value) {
  Statement put(db, "INSERT OR REPLACE INTO meta (key, value) VALUES (:key, :value)", path);
  put.bind(":key", key);
  put.bind(":value", value);
  put.step();
}

// a table's checksum as a write transaction finds it
Checksum stored_checksum(sqlite3* db, const std::string& path, const std::string& key) {
  const std::string text = meta_value(db, path, key);
  const auto sum = parse_checksum(text);
  if (!sum) damaged(path, "meta key '" + key + "' holds '" + shown(text) + "', not a checksum");
  return *sum;
}

// adds runs inside a write transaction: a run the store holds already is compared instead, and
// the runs' checksum is kept with them
// Inserts the points not stored yet and keeps the "check:points" checksum with them; finish()
// writes the checksum, inside the caller's transaction.
class PointWriter {
 public:
  PointWriter(sqlite3* db, const std::string& path)
      : db_(db),
        path_(path),
        put_(db,
             "INSERT OR IGNORE INTO points (sweep, point, axis_values, config_hash, config) "
             "VALUES (:sweep, :point, :axis_values, :config_hash, :config)",
             path),
        sum_(stored_checksum(db, path, "check:points")) {}

  void put(const StoredPoint& point) {
    put_.bind(":sweep", point.sweep);
    put_.bind(":point", static_cast<std::int64_t>(point.point));
    put_.bind(":axis_values", point.axis_values);
    put_.bind(":config_hash", point.config_hash);
    put_.bind(":config", point.config);
    put_.step();
    put_.reset();
    if (sqlite3_changes(db_) > 0) sum_.add(hash_of(point));
  }

  void finish() { put_meta(db_, path_, "check:points", sum_.text()); }

 private:
  sqlite3* db_;
  const std::string& path_;
  Statement put_;
  Checksum sum_;
};

class RunWriter {
 public:
  enum class Added { kNew, kSame, kDifferent };

  RunWriter(sqlite3* db, const std::string& path)
      : db_(db),
        path_(path),
        held_(db, held_sql().c_str(), path),
        put_(db, insert_run().c_str(), path),
        at_(columns(held_, put_)),
        sum_(stored_checksum(db, path, "check:runs")) {}

  Added add(const RunRow& r) {
    bind_key(held_, at_.key, r);
    const bool exists = held_.step();
    const bool same = exists && same_run(row_at(held_, at_.held, path_), r);
    held_.reset();
    if (exists) return same ? Added::kSame : Added::kDifferent;
    bind_run(put_, at_.put, r);
    put_.step();
    put_.reset();
    sum_.add(hash_of(r));
    return Added::kNew;
  }
  // writes the checksum (before the transaction commits)
  void finish() { put_meta(db_, path_, "check:runs", sum_.text()); }

 private:
  // the run of a key: every column where each member of the run key is a parameter
  static const std::string& held_sql() {
    static const std::string sql = [] {
      std::string where;
      for (const std::string_view name : kRunKeyFields) {
        where +=
            (where.empty() ? " WHERE " : " AND ") + std::string(name) + " = :" + std::string(name);
      }
      return std::string(kSelectRuns) + where;
    }();
    return sql;
  }
  // where the statements take and give each column
  struct Columns {
    RunColumnsAt held;                            // the columns of held's rows
    RunColumnsAt put;                             // the parameters of put
    std::array<int, kRunKeyFields.size()> key{};  // the parameters of held, in kRunKeyFields order
  };
  // why: a statement's text fixes where its columns are, and these texts never change, so they
  // are found once per process (a batch of 10 runs spent 3% of its time on it)
  static const Columns& columns(const Statement& held, const Statement& put) {
    static const Columns at = [&] {
      Columns c{run_columns_of(held), run_parameters(put), {}};
      for (std::size_t k = 0; k < kRunKeyFields.size(); ++k) {
        c.key[k] = held.parameter((":" + std::string(kRunKeyFields[k])).c_str());
      }
      return c;
    }();
    return at;
  }

  sqlite3* db_;
  const std::string& path_;
  Statement held_;
  Statement put_;
  const Columns& at_;
  Checksum sum_;
};

// switches the store to WAL journaling unless it is already; why: the switch needs the file to
// itself and SQLite does not wait for that, so when other processes open the same new store at
// once it is retried until one of them has switched it
void use_wal(sqlite3* db, const std::string& path) {
  const auto mode = [&](const char* sql, int& rc) {
    sqlite3_stmt* q = nullptr;
    rc = sqlite3_prepare_v2(db, sql, -1, &q, nullptr);
    if (rc == SQLITE_OK) rc = sqlite3_step(q);
    std::string text;
    if (rc == SQLITE_ROW) {
      const auto* p = sqlite3_column_text(q, 0);
      text = p ? reinterpret_cast<const char*>(p) : "";
      rc = SQLITE_OK;
    }
    sqlite3_finalize(q);
    return text;
  };
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    int rc = SQLITE_OK;
    if (mode("PRAGMA journal_mode", rc) == "wal" && rc == SQLITE_OK) return;
    if (rc == SQLITE_OK && mode("PRAGMA journal_mode=WAL", rc) == "wal" && rc == SQLITE_OK) return;
    const bool waited_enough =
        std::chrono::steady_clock::now() - start > std::chrono::milliseconds(kBusyTimeoutMs);
    if (rc != SQLITE_OK && ((rc & 0xff) != SQLITE_BUSY || waited_enough)) fail(db, rc, path);
    if (waited_enough) {
      throw StoreIoError("results store '" + path + "': cannot switch it to WAL journaling");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

// a new epoch for meta "epoch": made when a store is made or emptied (--fresh), so that a process
// that opened it before sees that its points may mean others now
std::string new_epoch() {
  std::random_device device;
  const auto now =
      static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  const std::uint64_t bits = (static_cast<std::uint64_t>(device()) << 32) ^ device() ^ now;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(bits));
  return hex;
}

// the points table without the configs (sweep, number, axis values, hash), ordered by (sweep,
// point), read inside a transaction
std::vector<StoredPoint> point_index(sqlite3* db, const std::string& path) {
  Statement q(db,
              "SELECT sweep, point, axis_values, config_hash, rowid FROM points ORDER BY sweep, "
              "point",
              path);
  const int sweep = q.column("sweep"), point = q.column("point"),
            axis_values = q.column("axis_values"), config_hash = q.column("config_hash"),
            rowid = q.column("rowid");
  std::vector<StoredPoint> points;
  while (q.step()) {
    const RowReader in(q, path, "row " + std::to_string(q.integer(rowid)) + " of table points");
    points.push_back(
        {in.text(sweep, "sweep"), static_cast<int>(in.integer(point, "point", 0, INT_MAX)),
         in.text(axis_values, "axis_values"), in.text(config_hash, "config_hash"), ""});
  }
  return points;
}

// the sweeps of a stored definition by name, with their master seeds as it writes them
std::map<std::string, std::string> stored_seeds(const std::string& definition) {
  std::map<std::string, std::string> seeds;
  const auto doc = nlohmann::json::parse(definition, nullptr, false);
  if (!doc.is_object() || !doc.contains("sweeps") || !doc["sweeps"].is_array()) return seeds;
  for (const auto& s : doc["sweeps"]) {
    if (s.is_object() && s.contains("name") && s["name"].is_string()) {
      seeds[s["name"].get<std::string>()] =
          s.contains("seed") && s["seed"].is_string() ? s["seed"].get<std::string>() : "";
    }
  }
  return seeds;
}

// the stored definition with each sweep of `campaign` (a campaign_definition) put in place of
// the stored sweep of its name, or added after the others
std::string joined_definition(const std::string& stored, const std::string& campaign) {
  auto doc = nlohmann::json::parse(stored, nullptr, false);
  auto add = nlohmann::json::parse(campaign);
  if (!doc.is_object() || !doc.contains("sweeps") || !doc["sweeps"].is_array()) return campaign;
  auto& sweeps = doc["sweeps"];
  for (auto& s : add["sweeps"]) {
    const auto same = std::find_if(sweeps.begin(), sweeps.end(), [&](const nlohmann::json& held) {
      return held.is_object() && held.contains("name") && held["name"] == s["name"];
    });
    if (same != sweeps.end()) {
      *same = std::move(s);
    } else {
      sweeps.push_back(std::move(s));
    }
  }
  return doc.dump();
}

// the numbers in the store of a sweep's points (-1 for a point it does not hold), given each
// point's axis values and scenario hash: the stored point whose scenario resolved alike is the
// same point, whatever its number. Throws StoreError when the store holds the sweep with another
// master seed, or a point of the same values whose scenario resolved otherwise (the runs would
// be of another sweep: another base scenario, [set] or --set)
void number_points(const std::string& path, const std::map<std::string, std::string>& seeds,
                   const std::string& sweep, const std::string& seed,
                   const std::vector<std::string>& axis_values,
                   const std::vector<std::string>& hashes, const std::vector<StoredPoint>& stored,
                   std::vector<int>& numbers, const std::string& hint) {
  const auto held_seed = seeds.find(sweep);
  if (held_seed != seeds.end() && !held_seed->second.empty() && held_seed->second != seed) {
    throw StoreError("results store '" + path + "' holds sweep '" + sweep +
                     "' run with master seed " + shown(held_seed->second) +
                     "; this sweep has seed " + seed + " (its runs would all differ)" + hint);
  }
  std::map<std::string, int> by_hash;
  std::map<std::string, const StoredPoint*> by_values;
  for (const auto& p : stored) {
    if (p.sweep != sweep) continue;
    by_hash.try_emplace(p.config_hash, p.point);
    by_values.try_emplace(p.axis_values, &p);
  }
  numbers.resize(hashes.size(), -1);
  for (std::size_t i = 0; i < hashes.size(); ++i) {
    const auto same = by_hash.find(hashes[i]);
    if (same != by_hash.end()) {
      numbers[i] = same->second;
      continue;
    }
    const auto alike = by_values.find(axis_values[i]);
    if (alike != by_values.end()) {
      throw StoreError(
          "results store '" + path + "' holds sweep '" + sweep + "' at point (" + axis_values[i] +
          ") with another resolved scenario than this sweep's (another base "
          "scenario, [set] or --set: scenario hash " +
          shown(alike->second->config_hash) + " there, " + hashes[i] + " here)" + hint);
    }
    numbers[i] = -1;
  }
}

// the stored runs of points numbered `numbers` in `sweep`, as `point` of the campaign: a row of
// a point the campaign has twice (the same scenario under two values) is given to both
std::vector<RunRow> renumbered(const std::vector<RunRow>& rows,
                               const std::map<std::pair<std::string, int>, std::vector<int>>& at) {
  std::vector<RunRow> out;
  for (const auto& r : rows) {
    const auto it = at.find({r.sweep, r.point});
    if (it == at.end()) continue;
    for (const int point : it->second) {
      RunRow copy = r;
      copy.point = point;
      out.push_back(std::move(copy));
    }
  }
  std::sort(out.begin(), out.end(),
            [](const RunRow& a, const RunRow& b) { return RunRow::key_of(a) < RunRow::key_of(b); });
  return out;
}

}  // namespace

Store::Store(const std::string& path, const std::vector<ExpandedSweep>& campaign,
             std::string_view version, bool fresh)
    : path_(path), definition_(campaign_definition(campaign)), bound_(true) {
  for (const auto& sweep : campaign) {
    CampaignSweep s{sweep.def.name, std::to_string(sweep.def.seed), {}, {}, {}};
    for (const auto& p : sweep.points) {
      s.axis_values.push_back(axis_values_text(sweep.def, p));
      s.hashes.push_back(p.config_hash);
    }
    s.numbers.assign(sweep.points.size(), -1);
    campaign_.push_back(std::move(s));
  }
  open(version, fresh);
}

Store::Store(const std::string& path, const std::string& definition, std::string_view version,
             bool fresh)
    : path_(path), definition_(definition) {
  open(version, fresh);
}

void Store::accept(const std::string& definition, const std::string& version, std::string_view want,
                   const std::vector<StoredPoint>& points, const std::string& hint) const {
  if (version != want) {
    throw StoreError("results store '" + path_ + "' was written by plumetrace " + version +
                     ", this is " + std::string(want) + hint);
  }
  if (!bound_) {
    if (definition != definition_) {
      throw StoreError("results store '" + path_ + "' holds runs of a different sweep definition" +
                       hint);
    }
    return;
  }
  const auto seeds = stored_seeds(definition);
  for (auto& s : campaign_) {
    number_points(path_, seeds, s.name, s.seed, s.axis_values, s.hashes, points, s.numbers, hint);
  }
}

void Store::open(std::string_view version, bool fresh) {
  db_ = open_db(path_, path_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  try {
    if (sqlite3_db_readonly(db_, "main") == 1) {
      throw StoreIoError("results store '" + path_ + "': cannot write it (a read-only file)");
    }
    const std::string discard = "; use --fresh to discard its runs, or another --store";
    // what the file holds, read before anything is written to it
    {
      ReadTransaction read(db_, path_);
      check_size(db_, path_);  // why: refused even with --fresh, as SQLite cannot be trusted on it
      std::string found;
      const Layout layout = layout_of(db_, path_, &found);
      if (layout == Layout::kForeign) not_a_store(path_, found);
      if (layout == Layout::kPlumetrace && !fresh) {
        StoreContents held;
        try {
          held = load(db_, path_);
        } catch (const StoreIoError&) {
          throw;
        } catch (const StoreError& e) {
          throw StoreError(e.what() + discard);
        }
        accept(held.info.definition, held.info.version, version, held.points, discard);
      }
    }
    // why: WAL with synchronous=NORMAL keeps every committed batch through a kill -9, and lets
    // readers read while another process writes
    use_wal(db_, path_);
    exec("PRAGMA synchronous=NORMAL;");
    in_transaction([&] {
      // again under the write lock: another process may have made the store meanwhile
      std::string found;
      const Layout layout = layout_of(db_, path_, &found);
      if (layout == Layout::kForeign) not_a_store(path_, found);
      if (layout == Layout::kPlumetrace && !fresh) {
        accept(meta("definition"), meta("version"), version, point_index(db_, path_),
               " (another process wrote it meanwhile)" + discard);
        const bool older_runs = table_columns(db_, path_, "runs") != schema_columns().at("runs");
        if (meta("schema") == kLegacySchema || older_runs) {
          // a store of schema 1 (no checksums) or one whose runs lack the agent: checked under
          // the write lock, its runs table made anew with every column (agent 0: a robot alone;
          // NULL for the result fields it lacks), and the checksums of what it holds now
          const StoreContents held = load(db_, path_);
          if (older_runs) add_missing_columns(db_, path_);
          const auto [runs, points] = checksums_of(held);
          put_meta(db_, path_, "check:runs", runs.text());
          put_meta(db_, path_, "check:points", points.text());
        }
        // a store of schema 1 to 3: its points are numbered in grid order, as schema 3 may
        // number them; it gains an epoch
        if (meta("schema") != kSchemaVersion) {
          put_meta(db_, path_, "schema", std::string(kSchemaVersion));
        }
        if (meta("epoch").empty()) put_meta(db_, path_, "epoch", new_epoch());
        epoch_ = meta("epoch");
        if (bound_) {
          const std::string joined = joined_definition(meta("definition"), definition_);
          if (joined != meta("definition")) put_meta(db_, path_, "definition", joined);
        }
        return;
      }
      // why: table runs is made anew, as a store of an older schema has other columns
      if (layout == Layout::kPlumetrace) {
        exec("DELETE FROM points; DELETE FROM meta;");
        for (auto& s : campaign_) s.numbers.assign(s.numbers.size(), -1);
      }
      exec("DROP TABLE IF EXISTS runs;" + schema_sql());
      epoch_ = new_epoch();
      for (const auto& [k, v] : {std::pair<std::string, std::string>{"definition", definition_},
                                 {"version", std::string(version)},
                                 {"schema", std::string(kSchemaVersion)},
                                 {"check:runs", Checksum{}.text()},
                                 {"check:points", Checksum{}.text()},
                                 {"epoch", epoch_}}) {
        put_meta(db_, path_, k, v);
      }
    });
  } catch (...) {
    sqlite3_close(db_);
    throw;
  }
}

Store::~Store() { sqlite3_close(db_); }

void Store::exec(const std::string& sql) const { exec_sql(db_, path_, sql); }

void Store::in_transaction(const std::function<void()>& work) {
  // why: IMMEDIATE takes the write lock first (waiting for another process's), where a read
  // turned write would fail at once with "database is locked"
  exec("BEGIN IMMEDIATE;");
  try {
    work();
    exec("COMMIT;");
  } catch (...) {
    // why: SQLite has rolled back already after some errors (a full disk); a failed rollback
    // must not hide the error that caused it
    if (!sqlite3_get_autocommit(db_)) sqlite3_exec(db_, "ROLLBACK;", nullptr, nullptr, nullptr);
    throw;
  }
}

std::string Store::meta(const std::string& key) const { return meta_value(db_, path_, key); }

std::string Store::definition() const { return meta("definition"); }

void Store::check_definition() const {
  // why: only --fresh renews the epoch; another process that adds points or sweeps leaves every
  // number this one knows as it was
  if (meta("epoch") != epoch_) {
    throw StoreError("results store '" + path_ +
                     "' was emptied for another definition by another process (--fresh?) while "
                     "this one wrote it; nothing more is written to it");
  }
}

void Store::find_points(bool all) const {
  if (!bound_) return;
  if (!all) {
    bool missing = false;
    for (const auto& s : campaign_) {
      missing = missing || std::find(s.numbers.begin(), s.numbers.end(), -1) != s.numbers.end();
    }
    if (!missing) return;
  }
  // points another process has recorded since
  const auto points = point_index(db_, path_);
  const auto seeds = stored_seeds(meta("definition"));
  for (auto& s : campaign_) {
    number_points(path_, seeds, s.name, s.seed, s.axis_values, s.hashes, points, s.numbers, "");
  }
}

std::vector<RunRow> Store::numbered(std::vector<RunRow> rows) const {
  if (!bound_) return rows;
  std::map<std::pair<std::string, int>, std::vector<int>> at;
  for (const auto& s : campaign_) {
    for (std::size_t i = 0; i < s.numbers.size(); ++i) {
      if (s.numbers[i] >= 0) at[{s.name, s.numbers[i]}].push_back(static_cast<int>(i));
    }
  }
  return renumbered(rows, at);
}

void Store::put_points(const std::vector<ExpandedSweep>& sweeps) {
  if (!bound_) throw std::logic_error("Store::put_points: a store without a campaign takes none");
  bool same = sweeps.size() == campaign_.size();
  for (std::size_t k = 0; same && k < sweeps.size(); ++k) {
    same = sweeps[k].def.name == campaign_[k].name &&
           sweeps[k].points.size() == campaign_[k].hashes.size();
    for (std::size_t i = 0; same && i < sweeps[k].points.size(); ++i) {
      same = sweeps[k].points[i].config_hash == campaign_[k].hashes[i];
    }
  }
  if (!same) throw std::logic_error("Store::put_points: not the campaign the store was opened for");
  std::vector<CampaignSweep> numbered = campaign_;
  in_transaction([&] {
    check_definition();
    const auto points = point_index(db_, path_);
    const auto seeds = stored_seeds(meta("definition"));
    std::map<std::string, int> next;
    for (const auto& p : points) next[p.sweep] = std::max(next[p.sweep], p.point + 1);
    PointWriter writer(db_, path_);
    for (std::size_t k = 0; k < sweeps.size(); ++k) {
      CampaignSweep& s = numbered[k];
      number_points(path_, seeds, s.name, s.seed, s.axis_values, s.hashes, points, s.numbers, "");
      // a point new to the store takes its sweep's next number; the same scenario twice in the
      // campaign is one point
      std::map<std::string, int> added;
      for (std::size_t i = 0; i < s.numbers.size(); ++i) {
        if (s.numbers[i] >= 0) continue;
        const auto [it, fresh_point] = added.try_emplace(s.hashes[i], next[s.name]);
        s.numbers[i] = it->second;
        if (!fresh_point) continue;
        ++next[s.name];
        writer.put({s.name, s.numbers[i], s.axis_values[i], s.hashes[i],
                    scenario_to_toml(sweeps[k].points[i].scenario, ConfigKeys::kOfTheRun)});
      }
    }
    writer.finish();
    // the --set each sweep ran with, for export and report (issue 22)
    for (const auto& sweep : sweeps) {
      put_meta(db_, path_, "sets:" + sweep.def.name, nlohmann::json(sweep.sets).dump());
    }
  });
  campaign_ = std::move(numbered);
}

void Store::insert(const std::vector<RunRow>& rows) {
  in_transaction([&] {
    check_definition();
    find_points(false);
    RunWriter writer(db_, path_);
    for (const auto& given : rows) {
      RunRow r = given;
      if (bound_) {
        const auto s = std::find_if(campaign_.begin(), campaign_.end(),
                                    [&](const CampaignSweep& c) { return c.name == r.sweep; });
        const int number = s == campaign_.end() || r.point < 0 ||
                                   static_cast<std::size_t>(r.point) >= s->numbers.size()
                               ? -1
                               : s->numbers[static_cast<std::size_t>(r.point)];
        if (number < 0) {
          throw std::logic_error("Store::insert: " + key_text(r) +
                                 " is not a recorded point of the campaign (put_points first)");
        }
        r.point = number;
      }
      if (writer.add(r) == RunWriter::Added::kDifferent) {
        throw StoreError("results store '" + path_ + "' already holds " + key_text(given) +
                         " with other results than the ones computed now (written by another "
                         "build of plumetrace?)");
      }
    }
    writer.finish();
  });
}

void Store::put_plan(const std::vector<std::pair<std::string, int>>& runs,
                     const std::string& shard) {
  in_transaction([&] {
    check_definition();
    write_plan(runs, shard);
  });
}

void Store::write_plan(const std::vector<std::pair<std::string, int>>& runs,
                       const std::string& shard) {
  for (const auto& [sweep, count] : runs) {
    const std::string key = "runs:" + sweep;
    const std::string old = meta(key);
    put_meta(db_, path_, key,
             std::to_string(std::max(count, old.empty() ? 0 : runs_value(path_, key, old))));
  }
  if (shard.empty()) {
    exec("DELETE FROM meta WHERE key = 'shard';");
  } else {
    put_meta(db_, path_, "shard", shard);
  }
}

StoreInfo Store::info() const {
  const ReadTransaction read(db_, path_);
  return load(db_, path_).info;
}

std::set<RunKey> Store::keys() const {
  const ReadTransaction read(db_, path_);
  find_points(true);
  std::map<std::pair<std::string, int>, std::vector<int>> at;
  for (const auto& s : campaign_) {
    for (std::size_t i = 0; i < s.numbers.size(); ++i) {
      if (s.numbers[i] >= 0) at[{s.name, s.numbers[i]}].push_back(static_cast<int>(i));
    }
  }
  Statement q(db_, ("SELECT " + run_key_list() + " FROM runs").c_str(), path_);
  std::set<RunKey> keys;
  while (q.step()) {
    RunRow r;
    int col = 0;
    RunRow::key_fields(r, [&](std::string_view, auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      if constexpr (std::is_same_v<T, std::string>) {
        value = q.text(col++);
      } else {
        value = static_cast<T>(q.integer(col++));
      }
    });
    if (!bound_) {
      keys.insert(run_key(r));
      continue;
    }
    const auto it = at.find({r.sweep, r.point});
    if (it == at.end()) continue;
    for (const int p : it->second) {
      r.point = p;
      keys.insert(run_key(r));
    }
  }
  return keys;
}

std::vector<RunRow> Store::rows() const {
  const ReadTransaction read(db_, path_);
  StoreContents held = load(db_, path_);
  find_points(true);
  return numbered(std::move(held.rows));
}

StoreContents read_store(const std::string& path) {
  const ReadOnlyStore store(path);
  const ReadTransaction read(store.db(), path);
  return load(store.db(), path);
}

StoreInfo read_store_info(const std::string& path) { return read_store(path).info; }

std::vector<RunRow> read_store_rows(const std::string& path, std::string* definition) {
  StoreContents c = read_store(path);
  if (definition) *definition = c.info.definition;
  return std::move(c.rows);
}

std::vector<RunRow> read_campaign_rows(const std::string& path,
                                       const std::vector<ExpandedSweep>& campaign) {
  const StoreContents held = read_store(path);
  const auto seeds = stored_seeds(held.info.definition);
  const std::string hint = "; give the sweep files and --set values the store was made with";
  std::map<std::pair<std::string, int>, std::vector<int>> at;
  for (const auto& sweep : campaign) {
    const std::string& name = sweep.def.name;
    const bool stored =
        seeds.count(name) > 0 || std::any_of(held.points.begin(), held.points.end(),
                                             [&](const StoredPoint& p) { return p.sweep == name; });
    if (!stored) {
      std::string names;
      for (const auto& [held_name, seed] : seeds) names += (names.empty() ? "" : ", ") + held_name;
      throw StoreError("results store '" + path + "' holds no runs of sweep '" + name +
                       "' (it holds " + (names.empty() ? "no sweep" : "sweeps " + names) +
                       "): it was not made from these sweep files");
    }
    std::vector<std::string> values, hashes;
    for (const auto& p : sweep.points) {
      values.push_back(axis_values_text(sweep.def, p));
      hashes.push_back(p.config_hash);
    }
    std::vector<int> numbers;
    number_points(path, seeds, name, std::to_string(sweep.def.seed), values, hashes, held.points,
                  numbers, hint);
    for (std::size_t i = 0; i < numbers.size(); ++i) {
      if (numbers[i] >= 0) at[{name, numbers[i]}].push_back(static_cast<int>(i));
    }
  }
  return renumbered(held.rows, at);
}

namespace {

// whether a file is a store to be made: empty, or a database without a plumetrace row (as a
// merge or sweep killed before its first commit leaves it)
bool is_blank(const std::string& path) {
  if (std::filesystem::file_size(path) == 0) return true;
  const ReadOnlyStore store(path);
  const ReadTransaction read(store.db(), path);
  return layout_of(store.db(), path) == Layout::kEmpty;
}

}  // namespace

MergeReport Store::absorb(const std::vector<std::string>& parts,
                          const std::vector<StoreContents>& contents,
                          const std::vector<std::pair<std::string, int>>& runs) {
  MergeReport report;
  in_transaction([&] {
    check_definition();
    // each part's points as this store numbers them: a point is found by its scenario (parts
    // may number the points of a sweep given more values otherwise); a point new to the store
    // takes its sweep's next number
    std::vector<std::map<std::pair<std::string, int>, int>> number_in(parts.size());
    {
      std::vector<StoredPoint> held = point_index(db_, path_);
      std::map<std::string, int> next;
      for (const auto& p : held) next[p.sweep] = std::max(next[p.sweep], p.point + 1);
      PointWriter points(db_, path_);
      for (std::size_t k = 0; k < parts.size(); ++k) {
        for (const auto& p : contents[k].points) {
          std::vector<int> number;
          try {
            number_points(path_, {}, p.sweep, "", {p.axis_values}, {p.config_hash}, held, number,
                          "");
          } catch (const StoreError& e) {
            throw StoreError("merge: '" + parts[k] +
                             "' and the points merged before it differ: " + e.what());
          }
          if (number[0] < 0) {
            StoredPoint added = p;
            added.point = next[p.sweep]++;
            points.put(added);
            number[0] = added.point;
            held.push_back(std::move(added));
          }
          number_in[k][{p.sweep, p.point}] = number[0];
        }
      }
      points.finish();
    }
    // which part each merged run came from, to name both files of an overlap
    std::map<RunKey, std::size_t> origin;
    RunWriter writer(db_, path_);
    for (std::size_t k = 0; k < parts.size(); ++k) {
      std::int64_t overlaps = 0;
      std::string first_overlap;
      std::size_t other = 0;
      for (const RunRow& given : contents[k].rows) {
        RunRow r = given;
        r.point = number_in[k].at({r.sweep, r.point});
        const auto [it, added] = origin.try_emplace(run_key(r), k);
        if (!added) {
          if (overlaps++ == 0) {
            first_overlap = key_text(r);
            other = it->second;
          }
          continue;
        }
        switch (writer.add(r)) {
          case RunWriter::Added::kNew:
            ++report.added;
            break;
          case RunWriter::Added::kSame:
            ++report.already;
            break;
          case RunWriter::Added::kDifferent:
            throw StoreError("merge: '" + path_ + "' already holds " + key_text(r) +
                             " with other results than '" + parts[k] +
                             "'; merge into a new --store");
        }
      }
      if (overlaps > 0) {
        throw StoreError("merge: '" + parts[k] + "' and '" + parts[other] + "' both hold " +
                         std::to_string(overlaps) + " run(s), e.g. " + first_overlap +
                         "; parts must be disjoint (each --shard i/n of one n, given once)");
      }
    }
    writer.finish();
    write_plan(runs, "");
    for (const auto& c : contents) {
      for (const auto& [sweep, sets] : c.info.sets) {
        put_meta(db_, path_, "sets:" + sweep, nlohmann::json(sets).dump());
      }
    }
  });
  return report;
}

MergeReport merge_stores(const std::vector<std::string>& parts, const std::string& out) {
  if (parts.empty()) throw StoreError("merge: no part store given");
  std::vector<StoreContents> contents;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::string& p = parts[k];
    contents.push_back(read_store(p));
    for (std::size_t j = 0; j < k; ++j) {
      if (std::filesystem::equivalent(parts[j], p)) {
        throw StoreError("merge: '" + p + "' is given twice (also as '" + parts[j] + "')");
      }
    }
    const StoreInfo& first = contents.front().info;
    const StoreInfo& info = contents.back().info;
    if (info.version != version()) {
      throw StoreError("merge: '" + p + "' was written by plumetrace " + info.version +
                       ", this is " + std::string(version()) +
                       "; merge with the version that computed the parts");
    }
    if (info.definition != first.definition) {
      throw StoreError("merge: '" + p + "' holds runs of another sweep definition than '" +
                       parts.front() + "' (another sweep file, seed or --set)");
    }
  }
  const std::string& definition = contents.front().info.definition;
  // an empty file at `out` (a merge killed early) is a new store; only a file this merge
  // created is removed again on failure (issue 22, G2: a 1-byte notes.txt given as --store was
  // taken for a blank store and deleted)
  const bool existed = std::filesystem::exists(out);
  if (existed) {
    for (const auto& p : parts) {
      if (std::filesystem::equivalent(out, p)) {
        throw StoreError("merge: the --store '" + out + "' is also given as a part");
      }
    }
    if (!is_blank(out)) {
      const StoreInfo held = read_store_info(out);
      if (held.definition != definition || held.version != version()) {
        throw StoreError("merge: the --store '" + out +
                         "' holds runs of another sweep definition or version than the parts; "
                         "merge into a new --store");
      }
    }
  }

  // the runs per point asked of each sweep: the most any part was asked for
  std::map<std::string, int> most;
  for (const auto& c : contents) {
    for (const auto& [sweep, runs] : c.info.runs) most[sweep] = std::max(most[sweep], runs);
  }
  MergeReport report;
  try {
    Store store(out, definition, version(), false);
    report = store.absorb(parts, contents, {most.begin(), most.end()});
    const StoreInfo merged = store.info();
    for (const auto& [sweep, points] : merged.points) {
      const std::int64_t expected = points * merged.runs.at(sweep);
      const std::int64_t present = merged.stored.at(sweep);
      if (present < expected) report.gaps.push_back({sweep, expected, present});
    }
    report.total = static_cast<std::int64_t>(store.keys().size());
  } catch (...) {
    if (!existed) {
      for (const char* suffix : {"", "-wal", "-shm"}) {
        std::error_code ignored;
        std::filesystem::remove(out + suffix, ignored);
      }
    }
    throw;
  }

  // shards of one count that no part holds, when runs are missing
  if (report.gaps.empty()) return report;
  int count = 0;
  std::set<int> given;
  for (const auto& c : contents) {
    int i = 0, n = 0;
    if (std::sscanf(c.info.shard.c_str(), "%d/%d", &i, &n) != 2 || (count && n != count)) {
      count = -1;
      break;
    }
    count = n;
    given.insert(i);
  }
  for (int i = 1; i <= count; ++i) {
    if (!given.count(i)) {
      report.missing_shards.push_back(std::to_string(i) + "/" + std::to_string(count));
    }
  }
  return report;
}

}  // namespace plumetrace
