// SPDX-License-Identifier: MIT
// A command line run through /bin/sh, with what it printed and its exit code: the tests that
// drive the fesph binary.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

namespace fesph::testing {

struct CommandResult {
  int code = 0;
  std::string out;  ///< what the command printed (its stderr too where it says 2>&1)
};

/// Runs `command` as given and reads its standard output to the end.
inline CommandResult runCommand(const std::string& command) {
  CommandResult r;
  FILE* p = popen(command.c_str(), "r");
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) r.out += buf;
  r.code = WEXITSTATUS(pclose(p));
  return r;
}

/// Starts `command` in a shell of its own (exec'd, so that a signal reaches the program) and
/// waits until `ready` holds (polled every 20 ms, up to 8 s); the child's pid, -1 when the fork
/// failed.
template <class Ready> pid_t startAndWait(const std::string& command, Ready ready) {
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  for (int k = 0; pid > 0 && k < 400 && !ready(); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  return pid;
}

/// Sends `signal` to `pid` and waits for it to end: its exit code, or -1 when a signal ended
/// it (SIGKILL always does).
inline int signalAndWait(pid_t pid, int signal) {
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace fesph::testing
