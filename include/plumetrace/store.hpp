#pragma once

#include <cstdint>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "plumetrace/sweep.hpp"

struct sqlite3;

namespace plumetrace {

/// A results store that cannot be opened, read or written, or holds another definition.
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Identifies a run within a campaign.
using RunKey = std::tuple<std::string, int, std::uint64_t>;

/// The embedded SQLite results store: one row per run, plus the campaign definition and the
/// program version. Every write is one transaction.
class Store {
 public:
  /// Opens or creates the store at `path` for a campaign definition (JSON) and version; refuses
  /// a store holding another definition or version unless `fresh`, which empties it first.
  Store(const std::string& path, const std::string& definition, std::string_view version,
        bool fresh);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  /// Records the points of the campaign (axis values and resolved configs), once.
  void put_points(const std::vector<ExpandedSweep>& sweeps);
  /// Appends runs in one transaction.
  void insert(const std::vector<RunRow>& rows);
  /// Keys of every stored run.
  std::set<RunKey> keys() const;
  /// Every stored run, ordered by (sweep, point, trial).
  std::vector<RunRow> rows() const;
  /// The stored definition (JSON).
  std::string definition() const;
  /// The file path.
  const std::string& path() const { return path_; }

 private:
  void exec(const std::string& sql) const;
  void in_transaction(const std::function<void()>& work);
  std::string meta(const std::string& key) const;

  std::string path_;
  sqlite3* db_ = nullptr;
};

/// Opens an existing store without checking its definition (for export and reports).
std::vector<RunRow> read_store_rows(const std::string& path, std::string* definition);

}  // namespace plumetrace
