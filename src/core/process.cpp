#include "plumetrace/core/process.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

extern char** environ;

namespace plumetrace {

namespace {

// "NAME" of "NAME=value"
std::string variable_name(const std::string& entry) { return entry.substr(0, entry.find('=')); }

// this process's environment with `env` set
std::vector<std::string> child_environment(const std::vector<std::string>& env) {
  std::vector<std::string> out;
  for (char** e = environ; e && *e; ++e) {
    const std::string entry(*e);
    bool replaced = false;
    for (const auto& set : env) replaced = replaced || variable_name(set) == variable_name(entry);
    if (!replaced) out.push_back(entry);
  }
  out.insert(out.end(), env.begin(), env.end());
  return out;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (auto& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

}  // namespace

int run_program(const std::vector<std::string>& argv, const std::vector<std::string>& env) {
  if (argv.empty()) return kProgramNotStarted;
  std::vector<std::string> args = argv;
  std::vector<std::string> environment = child_environment(env);
  std::vector<char*> arg_pointers = pointers(args);
  std::vector<char*> env_pointers = pointers(environment);

  // why: as std::system (POSIX): Ctrl-C goes to the program, which decides; this process
  // waits, ignoring SIGINT and SIGQUIT, and keeps SIGCHLD blocked so no handler reaps the child
  struct sigaction ignore {
  }, old_int{}, old_quit{};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGINT, &ignore, &old_int);
  sigaction(SIGQUIT, &ignore, &old_quit);
  sigset_t child, old_mask;
  sigemptyset(&child);
  sigaddset(&child, SIGCHLD);
  sigprocmask(SIG_BLOCK, &child, &old_mask);

  // the program starts with SIGINT and SIGQUIT at their defaults and this process's mask
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t defaults;
  sigemptyset(&defaults);
  if (old_int.sa_handler != SIG_IGN) sigaddset(&defaults, SIGINT);
  if (old_quit.sa_handler != SIG_IGN) sigaddset(&defaults, SIGQUIT);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setsigmask(&attr, &old_mask);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);

  pid_t pid = -1;
  int status = kProgramNotStarted;
  if (posix_spawn(&pid, args[0].c_str(), nullptr, &attr, arg_pointers.data(),
                  env_pointers.data()) == 0) {
    int raw = 0;
    pid_t waited;
    do {
      waited = waitpid(pid, &raw, 0);
    } while (waited < 0 && errno == EINTR);
    if (waited == pid) {
      status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
    }
  }
  posix_spawnattr_destroy(&attr);

  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGQUIT, &old_quit, nullptr);
  sigprocmask(SIG_SETMASK, &old_mask, nullptr);
  return status;
}

}  // namespace plumetrace
