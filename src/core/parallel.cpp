#include "plumetrace/core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace plumetrace {

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& job) {
  std::atomic<std::size_t> next{0};
  std::mutex failure_mutex;
  std::exception_ptr failure;
  const auto work = [&] {
    try {
      for (std::size_t i = next++; i < n; i = next++) job(i);
    } catch (...) {
      // why: an exception leaving a thread ends the process; the caller rethrows it instead
      const std::lock_guard lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next = n;
    }
  };
  std::vector<std::thread> pool;
  const auto wanted = static_cast<std::size_t>(std::max(1, threads));
  try {
    for (std::size_t t = 1; t < std::min(wanted, n); ++t) pool.emplace_back(work);
  } catch (const std::system_error&) {
    // why: the jobs share one counter, so fewer threads than asked only take longer
  }
  work();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace plumetrace
