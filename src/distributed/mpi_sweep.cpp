// The distributed runner over MPI: rank 0 owns the store and hands out blocks of plume groups;
// every rank computes them on its own threads. Only the main thread of a rank calls MPI.
#include <mpi.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <list>
#include <optional>
#include <thread>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/distributed/distributed.hpp"

namespace plumetrace {

namespace {

// the messages; a rank's messages to another arrive in the order they were sent
enum Tag : int {
  kRequest = 1,  // worker -> 0: "give me up to n groups" (int32 n)
  kWork,         // 0 -> worker: a block of groups (encode_groups)
  kNoMore,       // 0 -> worker: every group is handed out; finish yours
  kStop,         // 0 -> worker: stop; finish the running groups, send their rows
  kRows,         // worker -> 0: rows of finished groups (encode_rows)
  kBye,          // worker -> 0: nothing more comes from this worker
  kFarewell,     // 0 -> worker: nothing more comes from rank 0
};

using Clock = std::chrono::steady_clock;

// the exit code of a job ended with ranks unaccounted for: that of an interrupted command
constexpr int kAbandoned = 130;

// how long rank 0 waits, once stopping, for the rows of groups still running elsewhere
// why: short enough to commit and say so before a launcher that ends the job kills it (Open MPI
// sends SIGKILL about 1 s after SIGTERM); what does not arrive is computed by the next run
constexpr double kStopWait = 0.5;

// how long rank 0 waits, once every run is in, for the goodbye of a rank that has nothing left
// to do
// why: a live rank says it within milliseconds of being told there is no more; one that never
// does has died, and waiting for the launcher to end the job would hang where it does not
constexpr double kByeWait = 5.0;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

void check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int size = 0;
  MPI_Error_string(rc, text, &size);
  throw IoError(std::string("MPI: ") + what + ": " + std::string(text, size));
}

// sends without blocking, so two ranks sending each other large messages cannot deadlock
class Outbox {
 public:
  void post(int dest, Tag tag, std::vector<char> bytes) {
    Message& m = messages_.emplace_back();
    m.bytes = std::move(bytes);
    check(MPI_Isend(m.bytes.data(), static_cast<int>(m.bytes.size()), MPI_BYTE, dest, tag,
                    MPI_COMM_WORLD, &m.request),
          "send");
  }
  // forgets the messages that have left
  void progress() {
    for (auto it = messages_.begin(); it != messages_.end();) {
      int done = 0;
      check(MPI_Test(&it->request, &done, MPI_STATUS_IGNORE), "send");
      it = done ? messages_.erase(it) : std::next(it);
    }
  }
  // true when every message has left within `seconds`
  bool drain(double seconds) {
    const auto start = Clock::now();
    for (progress(); !messages_.empty() && since(start) < seconds; progress()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return messages_.empty();
  }

 private:
  struct Message {
    std::vector<char> bytes;
    MPI_Request request = MPI_REQUEST_NULL;
  };
  std::list<Message> messages_;  // why: a list, so buffers stay put while MPI reads them
};

struct Received {
  int source = 0;
  int tag = 0;
  std::vector<char> bytes;
};

// the next message from `source` (MPI_ANY_SOURCE: anyone), if one has come
std::optional<Received> poll(int source) {
  int found = 0;
  MPI_Message message;
  MPI_Status status;
  check(MPI_Improbe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &found, &message, &status), "probe");
  if (!found) return std::nullopt;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  Received r{status.MPI_SOURCE, status.MPI_TAG, std::vector<char>(static_cast<std::size_t>(count))};
  check(MPI_Mrecv(r.bytes.data(), count, MPI_BYTE, &message, MPI_STATUS_IGNORE), "receive");
  return r;
}

std::vector<char> encode_count(std::int32_t n) {
  std::vector<char> bytes(sizeof n);
  std::memcpy(bytes.data(), &n, sizeof n);
  return bytes;
}

std::int32_t decode_count(const std::vector<char>& bytes) {
  std::int32_t n = 0;
  if (bytes.size() != sizeof n) throw IoError("MPI: a malformed request");
  std::memcpy(&n, bytes.data(), sizeof n);
  return n;
}

// the test hook: (rank, blocks) from PLUMETRACE_TEST_KILL_RANK="r:m", or (-1, 0)
std::pair<int, int> kill_hook() {
  const char* v = std::getenv("PLUMETRACE_TEST_KILL_RANK");
  int rank = -1, blocks = 0;
  if (!v || std::sscanf(v, "%d:%d", &rank, &blocks) != 2) return {-1, 0};
  return {rank, blocks};
}

// what rank 0 knows of a worker
enum class Worker { kWorking, kToldNoMore, kToldStop, kGone };

CampaignResult coordinate(Ranks& ranks, const std::vector<ExpandedSweep>& sweeps,
                          const std::vector<RunTask>& tasks, const CampaignOptions& options,
                          const RowSink& sink, JobReport* report) {
  const auto start = Clock::now();
  const int threads = threads_per_rank(ranks, options.threads);
  int all_threads = 0;
  for (const int t : ranks.all_gather(threads)) all_threads += t;
  std::vector<std::int64_t> per_rank(static_cast<std::size_t>(ranks.size()), 0);

  // why: as run_tasks, split groups when there are too few for every thread of the job
  const auto groups =
      work_groups(sweeps, tasks, options.share_plumes, static_cast<std::size_t>(all_threads));
  std::deque<TaskGroup> queue(groups.begin(), groups.end());
  const auto hand_out = [&](std::int32_t n) {
    std::vector<TaskGroup> block;
    for (; n > 0 && !queue.empty(); --n) {
      block.push_back(std::move(queue.front()));
      queue.pop_front();
    }
    return block;
  };

  GroupPool pool(sweeps, threads, options.make_controller, options.stop);
  Outbox outbox;
  std::vector<Worker> workers(static_cast<std::size_t>(ranks.size()), Worker::kWorking);
  int present = ranks.size() - 1;
  bool stopping = false;
  Clock::time_point stop_time;
  const auto begin_stop = [&] {
    stopping = true;
    stop_time = Clock::now();
    pool.stop();
    for (int w = 1; w < ranks.size(); ++w) {
      auto& state = workers[static_cast<std::size_t>(w)];
      if (state == Worker::kGone || state == Worker::kToldStop) continue;
      outbox.post(w, kStop, {});
      state = Worker::kToldStop;
    }
  };

  CampaignResult result;
  result.total = static_cast<std::int64_t>(tasks.size());
  std::vector<RunRow> pending;
  std::int64_t received = 0;  // runs (tasks) from every rank, committed or pending
  std::optional<Clock::time_point> all_in;
  auto last_commit = Clock::now();
  const auto commit = [&] {
    if (!pending.empty()) {
      sink(pending);
      result.computed += runs_of(pending);
      pending.clear();
    }
    last_commit = Clock::now();
    if (options.on_progress) options.on_progress({result.computed, result.total, since(start)});
  };

  for (;;) {
    bool busy = false;
    if (!stopping && options.stop && options.stop->load()) begin_stop();
    // rank 0's own threads take blocks like any rank
    if (!stopping && pool.queued() == 0 && !queue.empty()) {
      pool.add(hand_out(threads));
      busy = true;
    }
    while (auto m = poll(MPI_ANY_SOURCE)) {
      busy = true;
      auto& state = workers[static_cast<std::size_t>(m->source)];
      if (m->tag == kRequest) {
        const std::int32_t wanted = decode_count(m->bytes);
        if (stopping) continue;  // it has been told to stop
        if (!queue.empty()) {
          outbox.post(m->source, kWork, encode_groups(hand_out(wanted)));
        } else {
          outbox.post(m->source, kNoMore, {});
          state = Worker::kToldNoMore;
        }
      } else if (m->tag == kRows) {
        auto rows = decode_rows(m->bytes);
        per_rank[static_cast<std::size_t>(m->source)] += runs_of(rows);
        received += runs_of(rows);
        for (auto& r : rows) pending.push_back(std::move(r));
      } else if (m->tag == kBye) {
        const bool early = state == Worker::kWorking;
        state = Worker::kGone;
        --present;
        outbox.post(m->source, kFarewell, {});
        // a worker that leaves before it was told there is no more was stopped (a signal)
        if (early && !stopping) begin_stop();
      }
    }
    GroupPool::Batch own = pool.take(busy ? 0.0 : 0.001);
    per_rank[0] += runs_of(own.rows);
    received += runs_of(own.rows);
    for (auto& r : own.rows) pending.push_back(std::move(r));
    outbox.progress();
    // a run of this rank failed (a controller's error): keep what is in, then end the job
    if (own.error && own.idle) {
      commit();
      std::rethrow_exception(own.error);
    }

    const bool done = present == 0 && own.idle && (queue.empty() || stopping);
    // why: once stopping, rows go to the store as they come, since the launcher may kill this
    // rank at any moment
    if (done || (stopping && !pending.empty()) || since(last_commit) >= options.progress_interval) {
      commit();
    }
    if (done) break;
    // a worker that died never says goodbye: past the wait, only this rank's own running groups
    // are waited for (they cannot be cut short, and their rows are kept as a local sweep keeps
    // them); with every run in, there is nothing to wait for
    if (stopping && own.idle && (since(stop_time) > kStopWait || received == result.total)) {
      commit();
      break;
    }
    // every run is in, yet a rank has not said goodbye: it died (the store is complete)
    if (!all_in && received == result.total && own.idle) all_in = Clock::now();
    if (all_in && since(*all_in) > kByeWait) {
      commit();
      break;
    }
    if (!busy && own.idle) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }

  if (!outbox.drain(1.0) || present > 0) ranks.abandon(kAbandoned);
  if (report) {
    report->runs_per_rank = per_rank;
    report->silent_ranks.clear();
    for (int w = 1; w < ranks.size(); ++w) {
      if (workers[static_cast<std::size_t>(w)] != Worker::kGone) report->silent_ranks.push_back(w);
    }
  }
  result.interrupted = result.computed < result.total;
  // why: the time spent waiting for the goodbye of a silent rank is not the sweep's
  result.elapsed = std::chrono::duration<double>((all_in ? *all_in : Clock::now()) - start).count();
  return result;
}

}  // namespace

bool mpi_enabled() { return true; }

std::string mpi_library() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int size = 0;
  MPI_Get_library_version(text, &size);
  const std::string full(text, static_cast<std::size_t>(size));
  return full.substr(0, full.find(','));  // "Open MPI v4.1.4, package: ..."
}

Ranks::Ranks() {
  if (!mpi_launched()) return;
  int provided = 0;
  // why: FUNNELED: only the main thread calls MPI; the worker threads only simulate
  check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "init");
  joined_ = true;
  // why: errors come back as codes, so rank 0 can say what failed instead of being cut off
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local);
  MPI_Comm_size(local, &local_size_);
  MPI_Comm_free(&local);
  if (provided < MPI_THREAD_FUNNELED) {
    throw ConfigError("MPI: the library gives no thread support (MPI_THREAD_FUNNELED)");
  }
}

Ranks::~Ranks() {
  if (!joined_) return;
  // why: MPI_Abort ends every rank with any launcher, where an exit without MPI_Finalize may
  // leave the others waiting
  if (abandon_code_ != 0) MPI_Abort(MPI_COMM_WORLD, abandon_code_);
  MPI_Finalize();
}

std::vector<int> Ranks::all_gather(int value) const {
  std::vector<int> all(static_cast<std::size_t>(size_), value);
  if (size_ > 1) {
    check(MPI_Allgather(&value, 1, MPI_INT, all.data(), 1, MPI_INT, MPI_COMM_WORLD), "gather");
  }
  return all;
}

std::string Ranks::broadcast(const std::string& text) const {
  if (size_ == 1) return text;
  auto size = static_cast<std::uint64_t>(text.size());
  check(MPI_Bcast(&size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "broadcast");
  std::string out = rank_ == 0 ? text : std::string(size, '\0');
  check(MPI_Bcast(out.data(), static_cast<int>(size), MPI_CHAR, 0, MPI_COMM_WORLD), "broadcast");
  return out;
}

TaskRunner coordinator(Ranks& ranks, JobReport* report) {
  return
      [&ranks, report](const std::vector<ExpandedSweep>& sweeps, const std::vector<RunTask>& tasks,
                       const CampaignOptions& options, const RowSink& sink) {
        return coordinate(ranks, sweeps, tasks, options, sink, report);
      };
}

bool serve_blocks(Ranks& ranks, const std::vector<ExpandedSweep>& sweeps,
                  const CampaignOptions& options) {
  const int threads = threads_per_rank(ranks, options.threads);
  ranks.all_gather(threads);
  const auto [kill_rank, kill_after] = kill_hook();
  GroupPool pool(sweeps, threads, options.make_controller, options.stop);
  Outbox outbox;
  bool asked = false, no_more = false, stopping = false;
  int blocks = 0;
  for (;;) {
    bool busy = false;
    if (!stopping && options.stop && options.stop->load()) {
      stopping = true;
      pool.stop();
    }
    // ask for a block when the threads have nothing queued behind the groups they run
    if (!no_more && !stopping && !asked && pool.queued() == 0) {
      outbox.post(0, kRequest, encode_count(threads));
      asked = true;
    }
    while (auto m = poll(0)) {
      busy = true;
      if (m->tag == kWork) {
        auto groups = decode_groups(m->bytes);
        if (ranks.rank() == kill_rank && ++blocks >= kill_after) {
          std::fprintf(stderr,
                       "plumetrace: test hook: rank %d dies on receiving a block of %zu group(s) "
                       "(and with the groups it runs)\n",
                       kill_rank, groups.size());
          std::raise(SIGKILL);
        }
        if (!stopping) pool.add(std::move(groups));
        asked = false;
      } else if (m->tag == kNoMore) {
        no_more = true;
        asked = false;
      } else if (m->tag == kStop) {
        stopping = true;
        pool.stop();
      }
    }
    GroupPool::Batch batch = pool.take(busy ? 0.0 : 0.001);
    if (!batch.rows.empty()) {
      outbox.post(0, kRows, encode_rows(batch.rows));
    }
    // a run failed (a controller's error): send what is done, then end the job
    if (batch.error && batch.idle) {
      outbox.drain(1.0);
      std::rethrow_exception(batch.error);
    }
    // the hook's other case: told there is no more before the m-th block, it dies once its
    // running groups' rows are sent, holding nothing
    if (ranks.rank() == kill_rank && no_more && batch.idle) {
      const bool sent = outbox.drain(1.0);
      std::fprintf(stderr, "plumetrace: test hook: rank %d dies holding no work%s\n", kill_rank,
                   sent ? "" : " (but its last rows were not sent within 1 s)");
      std::raise(SIGKILL);
    }
    outbox.progress();
    if (batch.idle && (stopping || (no_more && !asked))) break;
    if (!busy && batch.idle) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }

  // say goodbye, and wait for rank 0's, so that nothing it sent is left unread
  outbox.post(0, kBye, {});
  const auto start = Clock::now();
  bool farewell = false;
  while (!farewell && since(start) < 5.0) {
    while (auto m = poll(0)) farewell = farewell || m->tag == kFarewell;
    outbox.progress();
    if (!farewell) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (!outbox.drain(1.0) || !farewell) ranks.abandon(kAbandoned);
  return !stopping;
}

}  // namespace plumetrace
