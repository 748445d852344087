#include "plumetrace/store.hpp"

#include <sqlite3.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "plumetrace/io.hpp"

namespace plumetrace {

namespace {

// a prepared statement, finalized on scope exit
class Statement {
 public:
  Statement(sqlite3* db, const char* sql, const std::string& path) : db_(db), path_(path) {
    if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK) fail("prepare");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void bind(int i, const std::string& v) {
    sqlite3_bind_text(stmt_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
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
    if (rc != SQLITE_DONE) fail("step");
    return false;
  }
  void reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  std::string text(int col) const {
    const auto* p = sqlite3_column_text(stmt_, col);
    return p ? reinterpret_cast<const char*>(p) : "";
  }
  std::int64_t integer(int col) const { return sqlite3_column_int64(stmt_, col); }
  double real(int col) const {
    return sqlite3_column_type(stmt_, col) == SQLITE_NULL ? NAN : sqlite3_column_double(stmt_, col);
  }

 private:
  [[noreturn]] void fail(const char* what) const {
    throw StoreError("results store '" + path_ + "': " + what + ": " + sqlite3_errmsg(db_));
  }
  sqlite3* db_;
  std::string path_;
  sqlite3_stmt* stmt_ = nullptr;
};

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS points (
  sweep TEXT NOT NULL, point INTEGER NOT NULL, axis_values TEXT NOT NULL,
  config_hash TEXT NOT NULL, config TEXT NOT NULL,
  PRIMARY KEY (sweep, point));
CREATE TABLE IF NOT EXISTS runs (
  sweep TEXT NOT NULL, point INTEGER NOT NULL, trial INTEGER NOT NULL,
  seed TEXT NOT NULL, config_hash TEXT NOT NULL,
  outcome TEXT NOT NULL, success INTEGER NOT NULL, time_s REAL NOT NULL,
  d_t REAL NOT NULL, d_u REAL NOT NULL, overhead REAL, losses INTEGER NOT NULL,
  odor_fraction REAL NOT NULL, steps INTEGER NOT NULL, wind_samples INTEGER NOT NULL,
  PRIMARY KEY (sweep, point, trial));
)sql";

sqlite3* open_db(const std::string& path, bool create) {
  sqlite3* db = nullptr;
  const int flags = SQLITE_OPEN_READWRITE | (create ? SQLITE_OPEN_CREATE : 0);
  if (sqlite3_open_v2(path.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    const std::string msg = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw StoreError("cannot open results store '" + path + "': " + msg);
  }
  sqlite3_busy_timeout(db, 10000);
  return db;
}

void exec_sql(sqlite3* db, const std::string& path, const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string msg = err ? err : "unknown error";
    sqlite3_free(err);
    throw StoreError("results store '" + path + "': " + msg);
  }
}

Outcome outcome_from(const std::string& name) {
  for (const Outcome o : {Outcome::kSuccess, Outcome::kWall, Outcome::kTimeout, Outcome::kGaveUp}) {
    if (outcome_name(o) == name) return o;
  }
  return Outcome::kRunning;
}

std::vector<RunRow> select_rows(sqlite3* db, const std::string& path) {
  Statement q(db,
              "SELECT sweep, point, trial, seed, config_hash, outcome, time_s, d_t, d_u, overhead, "
              "losses, odor_fraction, steps, wind_samples FROM runs ORDER BY sweep, point, trial",
              path);
  std::vector<RunRow> rows;
  while (q.step()) {
    RunRow r;
    r.sweep = q.text(0);
    r.point = static_cast<int>(q.integer(1));
    r.trial = static_cast<std::uint64_t>(q.integer(2));
    r.config_hash = q.text(4);
    RunResult& m = r.result;
    m.seed = std::stoull(q.text(3));
    m.trial = r.trial;
    m.outcome = outcome_from(q.text(5));
    m.time = q.real(6);
    m.d_t = q.real(7);
    m.d_u = q.real(8);
    m.overhead = q.real(9);
    m.losses = static_cast<int>(q.integer(10));
    m.odor_fraction = q.real(11);
    m.steps = q.integer(12);
    m.wind_samples = q.integer(13);
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace

Store::Store(const std::string& path, const std::string& definition, std::string_view version,
             bool fresh)
    : path_(path) {
  db_ = open_db(path, true);
  try {
    // why: WAL with synchronous=NORMAL keeps every committed batch through a kill -9
    exec("PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;");
    exec(kSchema);
    const std::string stored = meta("definition");
    const std::string stored_version = meta("version");
    const bool empty = stored.empty();
    if (!empty && !fresh && stored != definition) {
      throw StoreError("results store '" + path +
                       "' holds runs of a different sweep definition; use another --store, or "
                       "--fresh to discard them");
    }
    if (!empty && !fresh && stored_version != version) {
      throw StoreError("results store '" + path + "' was written by plumetrace " + stored_version +
                       ", this is " + std::string(version) + "; use --fresh to discard its runs");
    }
    if (empty || fresh) {
      exec("BEGIN; DELETE FROM runs; DELETE FROM points; DELETE FROM meta;");
      Statement put(db_, "INSERT INTO meta (key, value) VALUES (?, ?)", path_);
      for (const auto& [k, v] : {std::pair<std::string, std::string>{"definition", definition},
                                 {"version", std::string(version)},
                                 {"schema", "1"}}) {
        put.bind(1, k);
        put.bind(2, v);
        put.step();
        put.reset();
      }
      exec("COMMIT;");
    }
  } catch (...) {
    sqlite3_close(db_);
    throw;
  }
}

Store::~Store() { sqlite3_close(db_); }

void Store::exec(const std::string& sql) const { exec_sql(db_, path_, sql); }

void Store::in_transaction(const std::function<void()>& work) {
  exec("BEGIN;");
  try {
    work();
    exec("COMMIT;");
  } catch (...) {
    exec("ROLLBACK;");
    throw;
  }
}

std::string Store::meta(const std::string& key) const {
  Statement q(db_, "SELECT value FROM meta WHERE key = ?", path_);
  q.bind(1, key);
  return q.step() ? q.text(0) : "";
}

std::string Store::definition() const { return meta("definition"); }

void Store::put_points(const std::vector<ExpandedSweep>& sweeps) {
  in_transaction([&] {
    Statement put(db_,
                  "INSERT OR IGNORE INTO points (sweep, point, axis_values, config_hash, config) "
                  "VALUES (?, ?, ?, ?, ?)",
                  path_);
    for (const auto& sweep : sweeps) {
      for (const auto& p : sweep.points) {
        std::string values;
        for (std::size_t a = 0; a < p.values.size(); ++a) {
          values += (a ? ", " : "") + sweep.def.axes[a].key + " = " + format_value(p.values[a]);
        }
        put.bind(1, sweep.def.name);
        put.bind(2, static_cast<std::int64_t>(p.index));
        put.bind(3, values);
        put.bind(4, p.config_hash);
        put.bind(5, scenario_to_toml(p.scenario));
        put.step();
        put.reset();
      }
    }
  });
}

void Store::insert(const std::vector<RunRow>& rows) {
  in_transaction([&] {
    Statement put(db_,
                  "INSERT INTO runs (sweep, point, trial, seed, config_hash, outcome, success, "
                  "time_s, d_t, d_u, overhead, losses, odor_fraction, steps, wind_samples) "
                  "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                  path_);
    for (const auto& r : rows) {
      const RunResult& m = r.result;
      put.bind(1, r.sweep);
      put.bind(2, static_cast<std::int64_t>(r.point));
      put.bind(3, static_cast<std::int64_t>(r.trial));
      put.bind(4, std::to_string(m.seed));  // why: TEXT keeps the full unsigned 64-bit seed
      put.bind(5, r.config_hash);
      put.bind(6, std::string(outcome_name(m.outcome)));
      put.bind(7, static_cast<std::int64_t>(m.outcome == Outcome::kSuccess));
      put.bind(8, m.time);
      put.bind(9, m.d_t);
      put.bind(10, m.d_u);
      put.bind(11, m.overhead);
      put.bind(12, static_cast<std::int64_t>(m.losses));
      put.bind(13, m.odor_fraction);
      put.bind(14, m.steps);
      put.bind(15, m.wind_samples);
      put.step();
      put.reset();
    }
  });
}

std::set<RunKey> Store::keys() const {
  Statement q(db_, "SELECT sweep, point, trial FROM runs", path_);
  std::set<RunKey> keys;
  while (q.step()) {
    keys.emplace(q.text(0), static_cast<int>(q.integer(1)),
                 static_cast<std::uint64_t>(q.integer(2)));
  }
  return keys;
}

std::vector<RunRow> Store::rows() const { return select_rows(db_, path_); }

std::vector<RunRow> read_store_rows(const std::string& path, std::string* definition) {
  if (!std::filesystem::is_regular_file(path)) {
    throw StoreError("cannot open results store '" + path + "': no such file");
  }
  sqlite3* db = open_db(path, false);
  try {
    if (definition) {
      Statement q(db, "SELECT value FROM meta WHERE key = 'definition'", path);
      *definition = q.step() ? q.text(0) : "";
    }
    auto rows = select_rows(db, path);
    sqlite3_close(db);
    return rows;
  } catch (...) {
    sqlite3_close(db);
    throw;
  }
}

}  // namespace plumetrace
