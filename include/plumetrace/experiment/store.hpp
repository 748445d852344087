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

/// What a store says about itself, besides its runs.
struct StoreInfo {
  std::string definition;                      ///< campaign definition (JSON)
  std::string version;                         ///< program version that wrote it
  std::string shard;                           ///< "i/n" when it holds one shard, else ""
  std::map<std::string, int> runs;             ///< runs per point asked of each sweep
  std::map<std::string, std::int64_t> points;  ///< points of each sweep
  /// Stored runs of each sweep: its (point, trial) with trial < runs that have rows, a trial
  /// counting once whatever its team's size (a team's rows are stored together).
  std::map<std::string, std::int64_t> stored;
  /// The --set each sweep ran with (ExpandedSweep::sets), where the store recorded them.
  std::map<std::string, std::vector<std::string>> sets;
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
  std::vector<RunRow> rows;         ///< ordered by (sweep, point, trial, agent)
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
  std::int64_t present = 0;   ///< stored runs (point, trial) with trial < runs per point
};

/// What merge_stores did.
struct MergeReport {
  std::int64_t added = 0;      ///< rows (one per robot of a run) copied into the store
  std::int64_t already = 0;    ///< rows the store already held, identical, so not copied
  std::int64_t total = 0;      ///< rows (one per robot of a run) in the store afterwards
  std::vector<SweepGap> gaps;  ///< sweeps with runs missing
  std::vector<std::string> missing_shards;  ///< "i/n" shards no part holds (all parts of n)
};

/// The embedded SQLite results store: one row per robot of a run, keyed by the run key
/// (kRunKeyFields: sweep, point, trial, agent), plus each sweep's definition, the
/// program version and a checksum of the runs and of the points. A point is identified by its
/// values: the store numbers the points of a sweep itself, in the order they were first stored,
/// and finds a campaign's points by the scenario they resolve to, so a sweep given more values
/// keeps every run already stored. Every write is one transaction; several processes may write
/// one store at once.
class Store {
 public:
  /// Opens or creates the store at `path` for a campaign and version, checked as read_store
  /// does before anything is written. An empty file (or a database without tables) is a new
  /// store. The store may hold other sweeps and other points of the campaign's sweeps (values
  /// added or removed since): the campaign uses the runs of the points it shares with it.
  /// Refuses another program's database, always; refuses a damaged store, one of another
  /// version, one holding a sweep of the same name with another master seed, or a point of the
  /// same values whose scenario resolved otherwise (another base scenario or --set), unless
  /// `fresh`, which empties it first.
  Store(const std::string& path, const std::vector<ExpandedSweep>& campaign,
        std::string_view version, bool fresh);
  /// Opens or creates a store without a campaign, whose rows carry the store's own point
  /// numbers (merge_stores, benchmarks); it must hold `definition` (JSON) and `version`, or be
  /// new, unless `fresh`, which empties it first.
  Store(const std::string& path, const std::string& definition, std::string_view version,
        bool fresh);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  /// Records the campaign's points that the store does not hold yet (axis values and resolved
  /// configs), each under its sweep's next free number; `sweeps` must be the store's campaign.
  void put_points(const std::vector<ExpandedSweep>& sweeps);
  /// Records the runs per point asked of each sweep (the largest asked so far is kept) and the
  /// shard the store holds ("i/n", "" for the whole campaign); `merge_stores` reads them.
  void put_plan(const std::vector<std::pair<std::string, int>>& runs, const std::string& shard);
  /// Appends runs in one transaction; a campaign's rows are numbered by its points, whose
  /// points put_points has recorded. A run the store already holds (another process computed
  /// it) is skipped when identical and refused otherwise, with StoreError.
  void insert(const std::vector<RunRow>& rows);
  /// Keys (sweep, point, trial, agent) of the stored rows of the campaign's points, numbered by
  /// them (of every stored row, for a store without a campaign).
  std::set<RunKey> keys() const;
  /// The stored runs of the campaign's points numbered by them (every stored run, for a store
  /// without a campaign), ordered by (sweep, point, trial, agent), checked as read_store does.
  std::vector<RunRow> rows() const;
  /// The stored definition (JSON): each sweep's as it was last opened with the store.
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
  void open(std::string_view version, bool fresh);
  void accept(const std::string& definition, const std::string& version, std::string_view want,
              const std::vector<StoredPoint>& points, const std::string& hint) const;
  void find_points(bool all) const;
  std::vector<RunRow> numbered(std::vector<RunRow> rows) const;

  /// A sweep of the campaign: what identifies its points, and their numbers in the store.
  struct CampaignSweep {
    std::string name;                      ///< sweep name
    std::string seed;                      ///< master seed, as the definition writes it
    std::vector<std::string> axis_values;  ///< per point: "key = value, ..."
    std::vector<std::string> hashes;       ///< per point: hash of the resolved scenario
    std::vector<int> numbers;              ///< per point: its number in the store, or -1
  };

  std::string path_;
  std::string definition_;
  bool bound_ = false;                           ///< opened for a campaign
  mutable std::vector<CampaignSweep> campaign_;  ///< the campaign's sweeps (when bound_)
  std::string epoch_;                            ///< the store's epoch when it was opened
  sqlite3* db_ = nullptr;
};

/// The runs of a campaign that the existing store at `path` holds (read-only, checked as
/// read_store does), numbered by the campaign's points, ordered by (sweep, point, trial,
/// agent). Throws
/// StoreError naming the file when a sweep of the campaign is not in the store, has another
/// master seed there, or has a stored point of the same values whose scenario resolved otherwise.
std::vector<RunRow> read_campaign_rows(const std::string& path,
                                       const std::vector<ExpandedSweep>& campaign);

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
