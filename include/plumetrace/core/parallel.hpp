#pragma once

#include <cstddef>
#include <functional>

namespace plumetrace {

/// Calls job(i) for every i in [0, n) on up to `threads` threads (the caller's among them), each
/// i once, in no particular order; job(i) must write only what belongs to i. Fewer threads than
/// asked are used when the system refuses more (the jobs only take longer). The first exception
/// a job throws stops the handing out of further jobs and is rethrown here once all have
/// stopped.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& job);

}  // namespace plumetrace
