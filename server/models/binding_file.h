// BindingFile: the version of a store's <cid>.sweepbind that a replica holds in memory, so that
// it notices with one stat() when another replica sharing the store renamed an edited binding
// over it, and re-reads it before serving the model again.
//
// BindingFile::open(file): opens `file` and keeps it open for as long as the BindingFile lives.
//   Every writer renames a new file over the name (io/files/durable_file.h), never writes in place,
//   so a version is an inode; holding it open keeps the kernel from giving its number to a new
//   file, and (device, inode, size, mtime) names this version for good. Throws io::LoadError
//   (missing, unreadable).
// bytes(): the whole file, read from the open descriptor — the very version open() found, even
//   if a rename replaced the name since (no window between the check and the read).
// size(): that version's bytes, as open() found them (what an edit's work is sized by).
// replaced(): true when the name now gives another version (one stat(), 0.8–2.5 µs on this
//   machine under load: server_bench); false when it gives this one, or none (missing
//   or unreadable: keep serving what is held). On NFS the answer is as fresh as the client's
//   attribute cache (actimeo: deploy/README.md).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

namespace sweepd::server {

class BindingFile {
 public:
  static std::shared_ptr<const BindingFile> open(const std::filesystem::path& file);
  ~BindingFile();
  BindingFile(const BindingFile&) = delete;
  BindingFile& operator=(const BindingFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::vector<std::uint8_t> bytes() const;
  std::uint64_t size() const { return static_cast<std::uint64_t>(version_.size); }
  bool replaced() const;

  struct Version {
    dev_t device = 0;
    ino_t inode = 0;
    off_t size = 0;
    std::int64_t mtime_ns = 0;
    bool operator==(const Version&) const = default;
  };

 private:
  BindingFile(std::filesystem::path path, int descriptor, Version version)
      : path_(std::move(path)), descriptor_(descriptor), version_(version) {}
  std::filesystem::path path_;
  int descriptor_;
  Version version_;
};

}  // namespace sweepd::server
