#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// True when this build can run a sweep across the processes of an MPI job.
bool mpi_enabled();

/// The MPI library of this build ("Open MPI v4.1.4"), or "" without MPI.
std::string mpi_library();

/// True when an MPI launcher (mpirun, mpiexec, srun) started this process, from its environment.
bool mpi_launched();

/// Processes in the job that started this process, from the launcher's environment without
/// starting MPI (1 when not started by a launcher, or when the launcher does not say).
int launched_ranks();

/// This process's place in an MPI job. Started by a launcher, it joins the job (initialises
/// MPI) and leaves it (finalises) when destroyed; otherwise it is a job of one. A class because
/// MPI is initialised and finalised once, and an abandoned job must be ended, not waited for.
class Ranks {
 public:
  /// Joins the job; throws ConfigError when a launcher started several processes of a build
  /// without MPI (each would run the whole sweep).
  Ranks();
  /// Leaves the job: MPI_Finalize, or MPI_Abort after abandon().
  ~Ranks();
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;

  /// This process's rank, 0 to size() - 1.
  int rank() const { return rank_; }
  /// Processes in the job.
  int size() const { return size_; }
  /// Processes of the job on this machine.
  int local_size() const { return local_size_; }
  /// Every rank's `value`, in rank order (collective: every rank calls it).
  std::vector<int> all_gather(int value) const;
  /// Rank 0's `text`, on every rank (collective).
  std::string broadcast(const std::string& text) const;
  /// Makes the destructor end the whole job with `code` (MPI_Abort) instead of waiting in
  /// MPI_Finalize for ranks that may be gone or still waiting for this one.
  void abandon(int code) { abandon_code_ = code; }
  /// True after abandon().
  bool abandoned() const { return abandon_code_ != 0; }

 private:
  int rank_ = 0;
  int size_ = 1;
  int local_size_ = 1;
  bool joined_ = false;
  int abandon_code_ = 0;
};

/// Worker threads for each rank: `threads` when positive, else this machine's cores shared
/// among the job's processes on it (at least one).
int threads_per_rank(const Ranks& ranks, int threads);

/// What rank 0 knows of the job's ranks once a sweep has ended.
struct JobReport {
  /// Runs each rank computed, by rank.
  std::vector<std::int64_t> runs_per_rank;
  /// Ranks that never said goodbye (they died, or the job was ended first), in rank order.
  std::vector<int> silent_ranks;
};

/// The TaskRunner of rank 0 in a job of several ranks. It splits the tasks into plume groups
/// (as run_tasks does, for the threads of every rank together), hands them out in blocks to
/// each rank that asks (one group per thread of that rank; rank 0 computes too, with its own
/// threads), and hands the rows to the sink as they arrive, every `progress_interval`. On
/// options.stop, or when a rank leaves early, it tells every rank to stop, keeps the rows that
/// still arrive for 0.5 s and those of its own running groups (each committed as it arrives),
/// and returns an interrupted result. Once every run is in, it waits 5 s at most for the
/// goodbye of the other ranks; a rank still silent then has died, and the job is abandoned
/// (ranks.abandoned()) although the result is complete. Every other rank must call
/// serve_blocks. `report` (may be null) receives what each rank did.
TaskRunner coordinator(Ranks& ranks, JobReport* report);

/// On ranks other than 0: computes the blocks that rank 0 hands out, on `options.threads`
/// threads (threads_per_rank), sending the rows of each finished group back, until rank 0 says
/// there are no more (true) or to stop, or options.stop is set (false).
/// Test hook: the environment variable PLUMETRACE_TEST_KILL_RANK="r:m" makes rank r kill
/// itself (SIGKILL) when its m-th block arrives, before computing it, or, when told there is no
/// more work before that, once the rows of its running groups are sent (saying which on
/// stderr), to test a rank that dies.
bool serve_blocks(Ranks& ranks, const std::vector<ExpandedSweep>& sweeps,
                  const CampaignOptions& options);

/// Rows as bytes for another rank of the same build: the run key (RunRow::key_fields), the
/// config hash, seed, the result's trial and agent and every stored result field; doubles
/// travel as their bits.
std::vector<char> encode_rows(const std::vector<RunRow>& rows);
/// The rows of encode_rows; throws IoError on a malformed message, an unknown outcome or an
/// agent outside a team (0 to kMaxTeam - 1).
std::vector<RunRow> decode_rows(const std::vector<char>& bytes);
/// Task groups as bytes for another rank of the same build.
std::vector<char> encode_groups(const std::vector<TaskGroup>& groups);
/// The groups of encode_groups; throws IoError on a malformed message.
std::vector<TaskGroup> decode_groups(const std::vector<char>& bytes);

}  // namespace plumetrace
