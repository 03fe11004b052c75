// SPDX-License-Identifier: MIT
#include "app/folder_lock.hpp"

#include "core/common/error.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

namespace fesph {

namespace {

struct Held {
  int fd;
  int users;
};

/// The locks this process holds, by folder: a second flock of the same file from another
/// descriptor would refuse the process its own lock.
std::map<std::string, Held>& heldLocks() {
  static std::map<std::string, Held> locks;
  return locks;
}

}  // namespace

std::string lockFile(const std::string& folder) {
  return (std::filesystem::path(folder) / ".fesph.lock").string();
}

FolderLock::~FolderLock() { release(); }

void FolderLock::release() {
  if (key_.empty()) return;
  auto it = heldLocks().find(key_);
  if (it != heldLocks().end() && --it->second.users == 0) {
    close(it->second.fd);  // closing the file releases its flock
    heldLocks().erase(it);
  }
  key_.clear();
}

bool FolderLock::held(const std::string& folder) {
  std::error_code ec;
  const std::string key = std::filesystem::weakly_canonical(folder, ec).string();
  if (!ec && heldLocks().count(key)) return true;
  const int fd = open(lockFile(folder).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;  // no lock file: no run of a fesph that locks
  const bool taken = flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  close(fd);  // releases the shared lock if it got one
  return taken;
}

std::string standingStatus(const std::string& folder, const std::string& status) {
  if (status != "running" || !std::filesystem::exists(lockFile(folder)) ||
      FolderLock::held(folder))
    return status;
  return "ended abruptly (killed or crashed)";
}

void FolderLock::take(const std::string& folder) {
  const std::string key = std::filesystem::weakly_canonical(folder).string();
  if (key == key_) return;
  auto it = heldLocks().find(key);
  if (it == heldLocks().end()) {
    const std::string path = lockFile(folder);
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw RunError("cannot create " + path + ": " + std::strerror(errno));
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int why = errno;
      std::string holder;
      std::getline(std::ifstream(path), holder);
      close(fd);
      if (why != EWOULDBLOCK) throw RunError("cannot lock " + path + ": " + std::strerror(why));
      throw RunError("another fesph run is writing into " + folder +
                     (holder.empty() ? "" : " (" + holder + ")") +
                     ": two runs in one folder would replace each other's files. Wait for it "
                     "to end, or give another output folder (--out)");
    }
    // Who holds it, for the message another run gets (the lock holds without the note).
    const std::string who = "process " + std::to_string(getpid());
    const bool noted = ftruncate(fd, 0) == 0 && write(fd, who.data(), who.size()) >= 0;
    (void)noted;
    it = heldLocks().emplace(key, Held{fd, 0}).first;
  }
  ++it->second.users;
  release();
  key_ = key;
}

}  // namespace fesph
