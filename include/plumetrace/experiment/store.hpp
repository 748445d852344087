#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"

struct sqlite3;

namespace plumetrace {

/// A results store that is not what it must be: missing, not a plumetrace store, damaged, or
/// holding another definition or version (bad input: exit code 2).
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A results store that the system could not open, read or write: permissions, a full disk, a
/// failed write, a lock another process held too long (an I/O failure: exit code 3).
class StoreIoError : public StoreError {
 public:
  using StoreError::StoreError;
};

/// Identifies a run within a campaign.
using RunKey = std::tuple<std::string, int, std::uint64_t>;

/// What a store says about itself, besides its runs.
struct StoreInfo {
  std::string definition;                      ///< campaign definition (JSON)
  std::string version;                         ///< program version that wrote it
  std::string shard;                           ///< "i/n" when it holds one shard, else ""
  std::map<std::string, int> runs;             ///< runs per point asked of each sweep
  std::map<std::string, std::int64_t> points;  ///< points of each sweep
  std::map<std::string, std::int64_t> stored;  ///< stored runs of each sweep (trial < runs)
};

/// A point of a sweep as a store holds it.
struct StoredPoint {
  std::string sweep;        ///< sweep name
  int point = 0;            ///< point index in the sweep
  std::string axis_values;  ///< "key = value, ..."
  std::string config_hash;  ///< hash of the point's resolved scenario
  std::string config;       ///< the resolved scenario (TOML)
};

/// Everything a store holds, checked: its file size fits its pages, its tables are a plumetrace
/// store's, every value has its column's type and range, every run matches its point, and the
/// runs and points match the checksums written with them.
struct StoreContents {
  StoreInfo info;                   ///< what it says about itself
  std::vector<StoredPoint> points;  ///< ordered by (sweep, point)
  std::vector<RunRow> rows;         ///< ordered by (sweep, point, trial)
};

/// Opens an existing store read-only (a store the user cannot write is read alike) and reads
/// and checks everything; throws StoreError naming the file (and the row and column) when it is
/// missing, not a plumetrace store or damaged, StoreIoError when it cannot be read.
StoreContents read_store(const std::string& path);

/// Reads an existing store's description (read_store without the rows).
StoreInfo read_store_info(const std::string& path);

/// Runs of one sweep that a merged store should hold, and how many it holds.
struct SweepGap {
  std::string sweep;          ///< sweep name
  std::int64_t expected = 0;  ///< points x runs per point
  std::int64_t present = 0;   ///< stored runs with trial < runs per point
};

/// What merge_stores did.
struct MergeReport {
  std::int64_t added = 0;      ///< runs copied into the store
  std::int64_t already = 0;    ///< runs the store already held, identical, so not copied
  std::int64_t total = 0;      ///< runs in the store afterwards
  std::vector<SweepGap> gaps;  ///< sweeps with runs missing
  std::vector<std::string> missing_shards;  ///< "i/n" shards no part holds (all parts of n)
};

/// The embedded SQLite results store: one row per run, plus the campaign definition, the
/// program version and a checksum of the runs and of the points. Every write is one
/// transaction; several processes may write one store at once.
class Store {
 public:
  /// Opens or creates the store at `path` for a campaign definition (JSON) and version, checked
  /// as read_store does before anything is written. An empty file (or a database without tables)
  /// is a new store. Refuses another program's database, always; refuses a damaged store or one
  /// holding another definition or version unless `fresh`, which empties it first.
  Store(const std::string& path, const std::string& definition, std::string_view version,
        bool fresh);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  /// Records the points of the campaign (axis values and resolved configs), once.
  void put_points(const std::vector<ExpandedSweep>& sweeps);
  /// Records the runs per point asked of each sweep (the largest asked so far is kept) and the
  /// shard the store holds ("i/n", "" for the whole campaign); `merge_stores` reads them.
  void put_plan(const std::vector<std::pair<std::string, int>>& runs, const std::string& shard);
  /// Appends runs in one transaction. A run the store already holds (another process computed
  /// it) is skipped when identical and refused otherwise, with StoreError.
  void insert(const std::vector<RunRow>& rows);
  /// Keys of every stored run.
  std::set<RunKey> keys() const;
  /// Every stored run, ordered by (sweep, point, trial), checked as read_store does.
  std::vector<RunRow> rows() const;
  /// The stored definition (JSON).
  std::string definition() const;
  /// What the store says about itself (definition, version, shard, runs and points per sweep).
  StoreInfo info() const;
  /// The file path.
  const std::string& path() const { return path_; }

 private:
  friend MergeReport merge_stores(const std::vector<std::string>& parts, const std::string& out);
  void exec(const std::string& sql) const;
  void write_plan(const std::vector<std::pair<std::string, int>>& runs, const std::string& shard);
  MergeReport absorb(const std::vector<std::string>& parts,
                     const std::vector<StoreContents>& contents,
                     const std::vector<std::pair<std::string, int>>& runs);
  void in_transaction(const std::function<void()>& work);
  std::string meta(const std::string& key) const;
  void check_definition() const;

  std::string path_;
  std::string definition_;
  sqlite3* db_ = nullptr;
};

/// The runs of an existing store (read_store), and its definition when asked.
std::vector<RunRow> read_store_rows(const std::string& path, std::string* definition);

/// Merges part stores (shards of one campaign) into the store at `out`, created if needed, in
/// one transaction. Every part, and `out` if it exists, must hold the same definition and
/// version, this program's; no run may be in two parts; a run `out` already holds is skipped
/// when identical and refused otherwise. Parts are opened read-only. An empty `out` (left by a
/// merge killed early) is a new store. Throws StoreError naming the files (and a run) and
/// changes nothing then.
MergeReport merge_stores(const std::vector<std::string>& parts, const std::string& out);

}  // namespace plumetrace
