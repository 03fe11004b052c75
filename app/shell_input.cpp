// SPDX-License-Identifier: MIT
// The line loop of `fesph shell`: GNU readline (history, tab completion) on a terminal, plain
// lines without prompt or echo from a script or a pipe. Ctrl-C pauses a run (the workbench's
// stop flag); at the prompt it clears the line.
#include "app/commands.hpp"
#include "app/shell.hpp"

#include <readline/history.h>
#include <readline/readline.h>

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace fesph {

namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_at_prompt{false};
const Workbench* g_bench = nullptr;  // for the completion callback
std::vector<std::string> g_matches;

void onInterrupt(int) {
  g_stop.store(true);
  if (g_at_prompt.load()) {  // readline calls this at a safe point, after its own cleanup
    std::fputc('\n', stdout);
    rl_on_new_line();
    rl_replace_line("", 0);
    rl_redisplay();
  }
}

char* nextMatch(const char*, int state) {
  static std::size_t k = 0;
  if (state == 0) k = 0;
  return k < g_matches.size() ? strdup(g_matches[k++].c_str()) : nullptr;
}

// Complete the word at [start, end) of rl_line_buffer from the words before it.
char** complete(const char* text, int start, int) {
  rl_attempted_completion_over = 1;  // never fall back to file names unasked
  std::vector<std::string> before;
  std::istringstream in(std::string(rl_line_buffer, static_cast<std::size_t>(start)));
  for (std::string w; in >> w;) before.push_back(w);
  g_matches = g_bench->completions(before, text);
  if (g_matches.size() == 1 && g_matches[0] == Workbench::kFiles)
    return rl_completion_matches(text, rl_filename_completion_function);
  // KEY= is followed by the value, not by a blank.
  rl_completion_append_character =
      g_matches.size() == 1 && !g_matches[0].empty() && g_matches[0].back() == '=' ? '\0' : ' ';
  return g_matches.empty() ? nullptr : rl_completion_matches(text, nextMatch);
}

std::string historyFile() {
  const char* home = std::getenv("HOME");
  return home ? std::string(home) + "/.fesph_history" : std::string();
}

}  // namespace

int shellCommand(const ShellOptions& options) {
  useThreads(options.threads);
  const bool interactive = isatty(STDIN_FILENO) && isatty(STDOUT_FILENO);
  Workbench bench(options, &g_stop, interactive);
  g_bench = &bench;

  struct sigaction sa = {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);

  bool all_ok = true;
  if (!options.path.empty()) all_ok &= bench.execute("load \"" + options.path + "\"");

  if (interactive) {
    std::printf("fesph %s workbench: `help` lists the commands, Tab completes, Ctrl-D leaves.\n",
                FESPH_VERSION);
    rl_readline_name = "fesph";
    rl_attempted_completion_function = complete;
    rl_completer_word_break_characters = const_cast<char*>(" \t");
    const std::string hist = historyFile();
    if (!hist.empty()) read_history(hist.c_str());
    while (!bench.done()) {
      g_at_prompt.store(true);
      char* raw = readline("fesph> ");
      g_at_prompt.store(false);
      if (!raw) {  // Ctrl-D
        std::printf("\n");
        break;
      }
      const std::string line = raw;
      std::free(raw);
      if (line.find_first_not_of(" \t") == std::string::npos) continue;
      add_history(line.c_str());
      bench.execute(line);
      std::fflush(stdout);
    }
    if (!hist.empty()) {
      write_history(hist.c_str());
      history_truncate_file(hist.c_str(), 1000);
    }
    return 0;
  }

  // A script or a pipe: no prompt, no echo; the exit code says whether every command worked.
  // Ctrl-C pauses the running command's run and ends the script.
  for (std::string line; !bench.done() && std::getline(std::cin, line);) {
    all_ok &= bench.execute(line);
    std::fflush(stdout);
    if (g_stop.load()) {
      std::fprintf(stderr, "interrupted: the rest of the script is not run\n");
      return 1;
    }
  }
  return all_ok ? 0 : 1;
}

}  // namespace fesph
