// StoreEditLock: an exclusive advisory lock on one model of a store, held across processes and
// hosts, so that replicas sharing the store edit a model one after the other: each edit reads
// the binding the last one stored and renames its result over it, and none is lost.
//
// StoreEditLock(lock_file): creates `lock_file` (store_dir/<cid>.lock, empty, never removed:
//   removing a lock file lets two processes lock two different files of one name) and waits
//   for flock(LOCK_EX) on it; released by the destructor, or by the kernel when the holder
//   dies (kill -9 included). Open descriptions, not processes, own the lock, so two registries
//   in one process exclude each other too. On NFS, Linux maps flock to a whole-file POSIX lock
//   (NLM or NFSv4), which other clients see. Throws std::runtime_error naming the file and the
//   reason when it cannot be created or locked.
#pragma once

#include <filesystem>

namespace sweepd::server {

class StoreEditLock {
 public:
  explicit StoreEditLock(const std::filesystem::path& lock_file);
  ~StoreEditLock();
  StoreEditLock(const StoreEditLock&) = delete;
  StoreEditLock& operator=(const StoreEditLock&) = delete;

 private:
  int descriptor_;
};

}  // namespace sweepd::server
