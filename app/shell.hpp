// SPDX-License-Identifier: MIT
// The workbench behind `fesph shell`: a loaded scene (or a finished run folder), the run being
// driven (RunSession), and the command table. Knows nothing of the terminal: the line editor
// (shell_input.cpp) hands it lines and asks it for completions.
#pragma once

#include "app/run_session.hpp"
#include "render/plate_images.hpp"

#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace fesph {

struct ShellOptions {
  std::string path;                    ///< scene or run folder to load at start; may be empty
  std::string out;                     ///< output folder of runs (default: the scene's)
  std::string materials;               ///< material library (default: found from the scene)
  std::vector<std::string> overrides;  ///< --set key=value given on the command line
  int threads = 0;                     ///< OpenMP threads of its runs; 0: the default
};

class Workbench {
 public:
  /// `stop` is set by Ctrl-C; a run checks it after every step.
  Workbench(ShellOptions options, std::atomic<bool>* stop, bool interactive);
  ~Workbench();

  /// Run one command line. Returns false when it failed (the message is already printed);
  /// no error ends the session. Sets done() on quit/exit.
  bool execute(const std::string& line);
  bool done() const { return done_; }

  /// Candidates for the word being completed, given the words before it. "\x01files" alone
  /// means: complete a file name.
  std::vector<std::string> completions(const std::vector<std::string>& before,
                                       const std::string& word) const;
  static const char* kFiles;

  /// Names of the commands, for the line editor.
  static std::vector<std::string> commandNames();

 private:
  struct Command;
  static const std::vector<Command>& table();

  // commands (argument words after the command's own)
  void load(const std::vector<std::string>& a);
  void show(const std::vector<std::string>& a);
  void set(const std::vector<std::string>& a);
  void meshInfo(const std::vector<std::string>& a);
  void run(const std::vector<std::string>& a);
  void stepN(const std::vector<std::string>& a);
  void render(const std::vector<std::string>& a);
  void plot(const std::vector<std::string>& a);
  void probe(const std::vector<std::string>& a);
  void compare(const std::vector<std::string>& a);
  void checkpoint(const std::vector<std::string>& a);
  void restart(const std::vector<std::string>& a);
  void exportCmd(const std::vector<std::string>& a);
  void report(const std::vector<std::string>& a);
  void help(const std::vector<std::string>& a);
  void quit(const std::vector<std::string>& a);

  /// The session, opened (meshed) now if the scene changed since. Throws when none is loaded.
  RunSession& session();
  /// Drive the session to `until` or by `steps` with Ctrl-C as the stop flag, and report.
  void advance(double until, long steps);
  /// summary.toml of the session's run with its status now: complete, failed or paused.
  void writeStatus() const;
  /// A run folder holding what is to be drawn: the model as it is now (written to
  /// RUN_FOLDER/shell/state, one series step with its scene.toml) or the loaded run folder.
  /// Sets `info` (bodies) and `time` (of the state drawn).
  std::string currentState(RunInfo& info, double& time);
  /// Folder of the current run (scene mode) or the loaded run folder.
  std::string runFolder() const;
  /// A scene is loaded and its run has written nothing yet: the folder holds an earlier run.
  bool nothingRunYet() const;
  /// Scene keys (dotted, arrays by index) of the current scene text, sorted.
  std::vector<std::string> sceneKeys() const;

  ShellOptions options_;
  std::atomic<bool>* stop_;
  bool interactive_;
  bool done_ = false;
  std::string scene_path_;               ///< loaded scene; empty: none
  std::string run_dir_;                  ///< loaded run folder (no scene); empty: none
  std::vector<std::string> overrides_;   ///< set key=value, in order
  std::string scene_text_;               ///< the scene with the overrides applied, as TOML
  std::unique_ptr<RunSession> session_;  ///< null until needed, and after a change
};

/// `fesph shell`: the line loop (readline on a terminal, plain lines from a script or pipe).
/// Exit code 0 when every command succeeded, 1 otherwise.
int shellCommand(const ShellOptions& options);

}  // namespace fesph
