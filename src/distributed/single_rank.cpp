// The distributed runner in a build without MPI: a job of one process.
#include <stdexcept>

#include "plumetrace/distributed/distributed.hpp"

namespace plumetrace {

bool mpi_enabled() { return false; }

std::string mpi_library() { return ""; }

Ranks::Ranks() {
  if (launched_ranks() > 1) {
    throw ConfigError("this plumetrace was built without MPI, so each of the " +
                      std::to_string(launched_ranks()) +
                      " processes the launcher started would run the whole sweep; rebuild with MPI "
                      "(libopenmpi-dev), or give each process its own --shard i/n and --store");
  }
}

Ranks::~Ranks() = default;

std::vector<int> Ranks::all_gather(int value) const { return {value}; }

std::string Ranks::broadcast(const std::string& text) const { return text; }

TaskRunner coordinator(Ranks&, JobReport*) {
  throw std::logic_error("coordinator: this build has no MPI");
}

bool serve_blocks(Ranks&, const std::vector<ExpandedSweep>&, const CampaignOptions&) {
  throw std::logic_error("serve_blocks: this build has no MPI");
}

}  // namespace plumetrace
