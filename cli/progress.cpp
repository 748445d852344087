#include "progress.hpp"

#include <unistd.h>

#include <csignal>
#include <cstdio>

namespace plumetrace::cli {

std::atomic<bool> g_stop{false};

namespace {

extern "C" void on_stop_signal(int sig) {
  g_stop.store(true);
  std::signal(sig, SIG_DFL);  // a second signal ends the process at once
}

std::string clock_text(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  }
  return buf;
}

}  // namespace

void install_stop_handlers() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

void ProgressBar::update(const Progress& p) {
  if (!enabled_ || p.total == 0) return;
  constexpr int kWidth = 30;
  const double fraction = static_cast<double>(p.done) / static_cast<double>(p.total);
  const int filled = static_cast<int>(fraction * kWidth);
  const double rate = p.elapsed > 0.0 ? static_cast<double>(p.done) / p.elapsed : 0.0;
  const std::string eta =
      rate > 0.0 ? clock_text(static_cast<double>(p.total - p.done) / rate) : "--:--";
  std::fprintf(stderr, "\r%s [%s%s] %lld/%lld runs  %.1f runs/s  ETA %s  ", label_.c_str(),
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(kWidth - filled), '.').c_str(),
               static_cast<long long>(p.done), static_cast<long long>(p.total), rate, eta.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (drawn_) std::fputc('\n', stderr);
  drawn_ = false;
}

}  // namespace plumetrace::cli
