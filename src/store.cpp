#include "plumetrace/store.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <bit>
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

constexpr const char* kRunColumns =
    "sweep, point, trial, seed, config_hash, outcome, time_s, d_t, d_u, overhead, losses, "
    "odor_fraction, steps, wind_samples";

// the row at the statement's cursor, selected with kRunColumns
RunRow row_at(const Statement& q) {
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
  return r;
}

std::vector<RunRow> select_rows(sqlite3* db, const std::string& path) {
  Statement q(
      db,
      (std::string("SELECT ") + kRunColumns + " FROM runs ORDER BY sweep, point, trial").c_str(),
      path);
  std::vector<RunRow> rows;
  while (q.step()) rows.push_back(row_at(q));
  return rows;
}

// binds a run to the parameters of kInsertRun
constexpr const char* kInsertRun =
    "INSERT INTO runs (sweep, point, trial, seed, config_hash, outcome, success, time_s, d_t, d_u, "
    "overhead, losses, odor_fraction, steps, wind_samples) "
    "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";

void bind_run(Statement& put, const RunRow& r) {
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
}

// same bits in every stored column (both rows read back from a store)
bool same_run(const RunRow& a, const RunRow& b) {
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  const RunResult& x = a.result;
  const RunResult& y = b.result;
  return a.config_hash == b.config_hash && x.seed == y.seed && x.outcome == y.outcome &&
         bits(x.time) == bits(y.time) && bits(x.d_t) == bits(y.d_t) && bits(x.d_u) == bits(y.d_u) &&
         bits(x.overhead) == bits(y.overhead) && x.losses == y.losses &&
         bits(x.odor_fraction) == bits(y.odor_fraction) && x.steps == y.steps &&
         x.wind_samples == y.wind_samples;
}

std::string meta_value(sqlite3* db, const std::string& path, const std::string& key) {
  Statement q(db, "SELECT value FROM meta WHERE key = ?", path);
  q.bind(1, key);
  return q.step() ? q.text(0) : "";
}

StoreInfo describe(sqlite3* db, const std::string& path) {
  StoreInfo info;
  info.definition = meta_value(db, path, "definition");
  info.version = meta_value(db, path, "version");
  info.shard = meta_value(db, path, "shard");
  {
    Statement q(db, "SELECT sweep, count(*) FROM points GROUP BY sweep", path);
    while (q.step()) info.points[q.text(0)] = q.integer(1);
  }
  for (const auto& [sweep, count] : info.points) {
    const std::string runs = meta_value(db, path, "runs:" + sweep);
    if (!runs.empty()) {
      info.runs[sweep] = std::stoi(runs);
    } else {
      // a store from before runs were recorded: as many as its largest trial says
      Statement q(db, "SELECT coalesce(max(trial) + 1, 0) FROM runs WHERE sweep = ?", path);
      q.bind(1, sweep);
      info.runs[sweep] = q.step() ? static_cast<int>(q.integer(0)) : 0;
    }
    Statement q(db, "SELECT count(*) FROM runs WHERE sweep = ? AND trial < ?", path);
    q.bind(1, sweep);
    q.bind(2, static_cast<std::int64_t>(info.runs[sweep]));
    info.stored[sweep] = q.step() ? q.integer(0) : 0;
  }
  return info;
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

std::string Store::meta(const std::string& key) const { return meta_value(db_, path_, key); }

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
    Statement put(db_, kInsertRun, path_);
    for (const auto& r : rows) {
      bind_run(put, r);
      put.step();
      put.reset();
    }
  });
}

void Store::put_plan(const std::vector<std::pair<std::string, int>>& runs,
                     const std::string& shard) {
  in_transaction([&] { write_plan(runs, shard); });
}

void Store::write_plan(const std::vector<std::pair<std::string, int>>& runs,
                       const std::string& shard) {
  Statement put(db_, "INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)", path_);
  const auto set = [&](const std::string& key, const std::string& value) {
    put.bind(1, key);
    put.bind(2, value);
    put.step();
    put.reset();
  };
  for (const auto& [sweep, count] : runs) {
    const std::string old = meta("runs:" + sweep);
    set("runs:" + sweep, std::to_string(std::max(count, old.empty() ? 0 : std::stoi(old))));
  }
  if (shard.empty()) {
    exec("DELETE FROM meta WHERE key = 'shard';");
  } else {
    set("shard", shard);
  }
}

StoreInfo Store::info() const { return describe(db_, path_); }

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

namespace plumetrace {

namespace {

// an existing store opened for reading, closed on scope exit
class OpenedStore {
 public:
  explicit OpenedStore(const std::string& path) : path_(path) {
    if (!std::filesystem::is_regular_file(path)) {
      throw StoreError("cannot open results store '" + path + "': no such file");
    }
    db_ = open_db(path, false);
  }
  ~OpenedStore() { sqlite3_close(db_); }
  OpenedStore(const OpenedStore&) = delete;
  OpenedStore& operator=(const OpenedStore&) = delete;

  sqlite3* db() const { return db_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

std::string key_text(const RunRow& r) {
  return "sweep " + r.sweep + ", point " + std::to_string(r.point) + ", trial " +
         std::to_string(r.trial);
}

}  // namespace

StoreInfo read_store_info(const std::string& path) {
  OpenedStore store(path);
  StoreInfo info;
  try {
    info = describe(store.db(), path);
  } catch (const StoreError& e) {
    throw StoreError("'" + path + "' is not a plumetrace results store (" + e.what() + ")");
  }
  if (info.definition.empty()) {
    throw StoreError("'" + path + "' is not a plumetrace results store (it has no definition)");
  }
  return info;
}

MergeReport Store::absorb(const std::vector<std::string>& parts,
                          const std::vector<std::pair<std::string, int>>& runs) {
  MergeReport report;
  in_transaction([&] {
    // which part each merged run came from, to name both files of an overlap
    exec(
        "CREATE TEMP TABLE IF NOT EXISTS merge_origin (sweep TEXT, point INTEGER, trial INTEGER, "
        "part INTEGER, PRIMARY KEY (sweep, point, trial)); DELETE FROM merge_origin;");
    Statement origin(
        db_, "SELECT part FROM merge_origin WHERE sweep = ? AND point = ? AND trial = ?", path_);
    Statement note(db_, "INSERT INTO merge_origin VALUES (?, ?, ?, ?)", path_);
    Statement held(db_,
                   (std::string("SELECT ") + kRunColumns +
                    " FROM runs WHERE sweep = ? AND point = ? AND trial = ?")
                       .c_str(),
                   path_);
    Statement put(db_, kInsertRun, path_);
    Statement put_point(db_,
                        "INSERT OR IGNORE INTO points (sweep, point, axis_values, config_hash, "
                        "config) VALUES (?, ?, ?, ?, ?)",
                        path_);
    const auto bind_key = [](Statement& q, const RunRow& r) {
      q.bind(1, r.sweep);
      q.bind(2, static_cast<std::int64_t>(r.point));
      q.bind(3, static_cast<std::int64_t>(r.trial));
    };
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const OpenedStore part(parts[k]);
      {
        Statement q(part.db(), "SELECT sweep, point, axis_values, config_hash, config FROM points",
                    parts[k]);
        while (q.step()) {
          put_point.bind(1, q.text(0));
          put_point.bind(2, q.integer(1));
          for (int c = 2; c < 5; ++c) put_point.bind(c + 1, q.text(c));
          put_point.step();
          put_point.reset();
        }
      }
      std::int64_t overlaps = 0;
      std::string first_overlap;
      std::size_t other = 0;
      for (const RunRow& r : select_rows(part.db(), parts[k])) {
        bind_key(origin, r);
        if (origin.step()) {
          if (overlaps++ == 0) {
            first_overlap = key_text(r);
            other = static_cast<std::size_t>(origin.integer(0));
          }
          origin.reset();
          continue;
        }
        origin.reset();
        bind_key(note, r);
        note.bind(4, static_cast<std::int64_t>(k));
        note.step();
        note.reset();
        bind_key(held, r);
        const bool exists = held.step();
        const RunRow stored = exists ? row_at(held) : RunRow{};
        held.reset();
        if (exists && !same_run(stored, r)) {
          throw StoreError("merge: '" + path_ + "' already holds " + key_text(r) +
                           " with other results than '" + parts[k] + "'; merge into a new --store");
        }
        if (exists) {
          ++report.already;
          continue;
        }
        bind_run(put, r);
        put.step();
        put.reset();
        ++report.added;
      }
      if (overlaps > 0) {
        throw StoreError("merge: '" + parts[k] + "' and '" + parts[other] + "' both hold " +
                         std::to_string(overlaps) + " run(s), e.g. " + first_overlap +
                         "; parts must be disjoint (each --shard i/n of one n, given once)");
      }
    }
    write_plan(runs, "");
    exec("DROP TABLE merge_origin;");
  });
  return report;
}

MergeReport merge_stores(const std::vector<std::string>& parts, const std::string& out) {
  if (parts.empty()) throw StoreError("merge: no part store given");
  std::vector<StoreInfo> infos;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::string& p = parts[k];
    for (std::size_t j = 0; j < k; ++j) {
      if (std::filesystem::equivalent(parts[j], p)) {
        throw StoreError("merge: '" + p + "' is given twice (also as '" + parts[j] + "')");
      }
    }
    infos.push_back(read_store_info(p));
    const StoreInfo& first = infos.front();
    const StoreInfo& info = infos.back();
    if (info.definition != first.definition) {
      throw StoreError("merge: '" + p + "' holds runs of another sweep definition than '" +
                       parts.front() + "' (another sweep file, seed or --set)");
    }
    if (info.version != first.version) {
      throw StoreError("merge: '" + p + "' was written by plumetrace " + info.version + ", '" +
                       parts.front() + "' by " + first.version);
    }
  }
  const bool existed = std::filesystem::exists(out);
  if (existed) {
    for (const auto& p : parts) {
      if (std::filesystem::equivalent(out, p)) {
        throw StoreError("merge: the --store '" + out + "' is also given as a part");
      }
    }
    const StoreInfo held = read_store_info(out);
    if (held.definition != infos.front().definition || held.version != infos.front().version) {
      throw StoreError("merge: the --store '" + out +
                       "' holds runs of another sweep definition or version than the parts; "
                       "merge into a new --store");
    }
  }

  // the runs per point asked of each sweep: the most any part was asked for
  std::map<std::string, int> most;
  for (const auto& info : infos) {
    for (const auto& [sweep, runs] : info.runs) most[sweep] = std::max(most[sweep], runs);
  }
  MergeReport report;
  try {
    Store store(out, infos.front().definition, infos.front().version, false);
    report = store.absorb(parts, {most.begin(), most.end()});
    const StoreInfo merged = store.info();
    for (const auto& [sweep, points] : merged.points) {
      const std::int64_t expected = points * merged.runs.at(sweep);
      const std::int64_t present = merged.stored.at(sweep);
      if (present < expected) report.gaps.push_back({sweep, expected, present});
    }
    report.total = static_cast<std::int64_t>(store.keys().size());
  } catch (...) {
    if (!existed) {
      for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(out + suffix);
    }
    throw;
  }

  // shards of one count that no part holds, when runs are missing
  if (report.gaps.empty()) return report;
  int count = 0;
  std::set<int> given;
  for (const auto& info : infos) {
    int i = 0, n = 0;
    if (std::sscanf(info.shard.c_str(), "%d/%d", &i, &n) != 2 || (count && n != count)) {
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
