// What the distributed runner needs with or without MPI: the launcher's environment, thread
// counts and the messages' byte format.
#include "plumetrace/distributed/distributed.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <type_traits>

#include "plumetrace/core/errors.hpp"

namespace plumetrace {

namespace {

// why: all ranks run the same build on the same kind of machine (an MPI job), so values travel
// as their native bytes, doubles with every bit
class Writer {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t at = bytes_.size();
    bytes_.resize(at + sizeof value);
    std::memcpy(bytes_.data() + at, &value, sizeof value);
  }
  void put(const std::string& text) {
    put(static_cast<std::uint32_t>(text.size()));
    bytes_.insert(bytes_.end(), text.begin(), text.end());
  }
  void reserve(std::size_t size) { bytes_.reserve(size); }
  std::vector<char> take() { return std::move(bytes_); }

 private:
  std::vector<char> bytes_;
};

class Reader {
 public:
  explicit Reader(const std::vector<char>& bytes) : bytes_(bytes) {}
  template <typename T>
  T get() {
    T value;
    need(sizeof value);
    std::memcpy(&value, bytes_.data() + at_, sizeof value);
    at_ += sizeof value;
    return value;
  }
  std::string text() {
    const auto size = get<std::uint32_t>();
    need(size);
    std::string out(bytes_.data() + at_, size);
    at_ += size;
    return out;
  }
  void expect_end() const {
    if (at_ != bytes_.size()) throw IoError("MPI: a message has bytes left over");
  }

 private:
  void need(std::size_t n) const {
    if (bytes_.size() - at_ < n) throw IoError("MPI: a message ends too early");
  }
  const std::vector<char>& bytes_;
  std::size_t at_ = 0;
};

int env_int(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : 0;
}

}  // namespace

bool mpi_launched() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMI_RANK", "PMIX_RANK"}) {
    if (std::getenv(name)) return true;
  }
  return false;
}

int launched_ranks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (const int n = env_int(name); n > 0) return n;
  }
  // srun with PMIx says the size only through Slurm's own variables
  if (std::getenv("PMIX_RANK") && env_int("SLURM_NTASKS") > 0) return env_int("SLURM_NTASKS");
  return 1;
}

int threads_per_rank(const Ranks& ranks, int threads) {
  if (threads > 0) return threads;
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return std::max(1, cores / std::max(1, ranks.local_size()));
}

namespace {

// a key member's or result field's value as it travels: an outcome and an int as a 32-bit
// integer, any other as it is
template <class T>
auto on_wire(const T& value) {
  if constexpr (std::is_same_v<T, Outcome> || std::is_same_v<T, int>) {
    return static_cast<std::int32_t>(value);
  } else {
    return value;
  }
}

// the bytes of a row in a message, besides its two texts (sweep, config_hash): the rest of its
// key, its seed, the result's trial and agent, and its result fields
const std::size_t kRowBytes = [] {
  std::size_t n = 2 * sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t) + sizeof(std::int32_t);
  RunRow::key_fields(RunRow{}, [&](std::string_view, const auto& value) {
    if constexpr (!std::is_same_v<std::remove_cvref_t<decltype(value)>, std::string>) {
      n += sizeof(on_wire(value));
    }
  });
  const RunResult r{};
  RunResult::fields(r, [&](const ResultField&, auto&& value) {
    if constexpr (!kDerivedField<decltype(value)>) n += sizeof(on_wire(value));
  });
  return n;
}();

}  // namespace

std::vector<char> encode_rows(const std::vector<RunRow>& rows) {
  Writer w;
  std::size_t size = sizeof(std::uint32_t);
  for (const RunRow& r : rows) size += kRowBytes + r.sweep.size() + r.config_hash.size();
  w.reserve(size);
  w.put(static_cast<std::uint32_t>(rows.size()));
  for (const RunRow& r : rows) {
    RunRow::key_fields(r, [&](std::string_view, const auto& value) { w.put(on_wire(value)); });
    w.put(r.config_hash);
    w.put(r.result.seed);
    w.put(r.result.trial);
    w.put(on_wire(r.result.agent));
    RunResult::fields(r.result, [&](const ResultField&, auto&& value) {
      if constexpr (!kDerivedField<decltype(value)>) w.put(on_wire(value));
    });
  }
  return w.take();
}

namespace {

// why: a robot's index is one of a team's, 0 to kMaxTeam - 1, as an outcome is a known one
void check_agent(std::int64_t value) {
  if (value < 0 || value >= kMaxTeam) throw IoError("MPI: a message holds an unknown agent");
}

}  // namespace

std::vector<RunRow> decode_rows(const std::vector<char>& bytes) {
  Reader in(bytes);
  std::vector<RunRow> rows(in.get<std::uint32_t>());
  for (RunRow& r : rows) {
    RunRow::key_fields(r, [&](std::string_view name, auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      if constexpr (std::is_same_v<T, std::string>) {
        value = in.text();
      } else {
        value = static_cast<T>(in.get<decltype(on_wire(value))>());
        if (name == "agent") check_agent(static_cast<std::int64_t>(value));
      }
    });
    r.config_hash = in.text();
    r.result.seed = in.get<std::uint64_t>();
    r.result.trial = in.get<std::uint64_t>();
    r.result.agent = in.get<std::int32_t>();
    check_agent(r.result.agent);
    RunResult::fields(r.result, [&](const ResultField&, auto&& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      if constexpr (kDerivedField<decltype(value)>) {
        return;
      } else if constexpr (std::is_same_v<T, Outcome>) {
        const auto code = in.get<std::int32_t>();
        if (code < 0 || static_cast<std::size_t>(code) >= kOutcomeNames.size()) {
          throw IoError("MPI: a message holds an unknown outcome");
        }
        value = static_cast<Outcome>(code);
      } else {
        value = in.get<T>();
      }
    });
  }
  in.expect_end();
  return rows;
}

std::vector<char> encode_groups(const std::vector<TaskGroup>& groups) {
  Writer w;
  w.put(static_cast<std::uint32_t>(groups.size()));
  for (const TaskGroup& g : groups) {
    w.put(static_cast<std::uint32_t>(g.size()));
    for (const RunTask& t : g) {
      w.put(static_cast<std::int32_t>(t.sweep));
      w.put(static_cast<std::int32_t>(t.point));
      w.put(t.trial);
    }
  }
  return w.take();
}

std::vector<TaskGroup> decode_groups(const std::vector<char>& bytes) {
  Reader in(bytes);
  std::vector<TaskGroup> groups(in.get<std::uint32_t>());
  for (TaskGroup& g : groups) {
    g.resize(in.get<std::uint32_t>());
    for (RunTask& t : g) {
      t.sweep = in.get<std::int32_t>();
      t.point = in.get<std::int32_t>();
      t.trial = in.get<std::uint64_t>();
    }
  }
  in.expect_end();
  return groups;
}

}  // namespace plumetrace
