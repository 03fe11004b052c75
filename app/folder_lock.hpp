// SPDX-License-Identifier: MIT
// One run at a time in a run folder. Two fesph runs into one folder (a `fesph run` and a shell
// on the same scene, say) each replace the other's series, histories and checkpoints as they
// go, leaving files of neither run. The lock is an flock on FOLDER/.fesph.lock, held as long as
// a run's session lives; the system releases it when the process ends, however it ends.
#pragma once

#include <string>

namespace fesph {

class FolderLock {
 public:
  FolderLock() = default;
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

  /// Take the lock of `folder` (which exists), releasing the one held before. Sessions of one
  /// process share it (the shell's restart opens its new session before it lets the old one
  /// go). Throws RunError naming the process that holds it.
  void take(const std::string& folder);
  void release();

  /// Whether a run (of this process or another) holds `folder` now: a summary.toml that
  /// says "running" of a folder nobody holds is of a run killed before it could say more.
  static bool held(const std::string& folder);

 private:
  std::string key_;  ///< the folder's canonical path; empty: none held
};

/// The lock file of `folder`: FOLDER/.fesph.lock.
std::string lockFile(const std::string& folder);

/// A run folder's summary.toml status as it stands now: "running" of a folder that holds the
/// lock file and no run holds is "ended abruptly (killed or crashed)"; any other as it is.
std::string standingStatus(const std::string& folder, const std::string& status);

}  // namespace fesph
