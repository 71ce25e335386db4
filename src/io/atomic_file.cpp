// Whole-or-nothing file writes: a reader (or a crash) never sees a half-written result, and a
// failed run leaves the previous file, if any, untouched.
//
// One fsync, of the new file before it is renamed, is what that takes: after a power cut the
// name then holds either the old file or the whole new one. The folder is not synchronised
// after the rename: that would only make the new name itself survive a power cut in the moment
// after the command returns (the previous file, or none, would be found instead, whole), and it
// cost each run another 6–8 ms waiting for the disk (bench/README.md).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <string>
#include <string_view>
#include <system_error>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/atomic_file.hpp"
#include "stiffmsa/io/result_file.hpp"

namespace stiffmsa {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int error) { return std::generic_category().message(error); }

[[noreturn]] void fail(const fs::path& path, const std::string& step, int error) {
  throw IoError("cannot write '" + path.string() + "': " + step + ": " + errno_text(error));
}

// Owns the temporary file until it has been renamed over the target; until then, any exit
// from the scope (error or exception) removes it.
class TemporaryFile {
 public:
  TemporaryFile(const fs::path& target, const fs::path& folder) : target_(target) {
    static std::atomic<unsigned> counter{0};
    // O_EXCL makes a clash with another writer (or a stale file) fail rather than share a
    // file, so we just try the next name.
    constexpr int max_attempts = 100;
    // Hidden, and named after the target, so that a leftover from a killed run is recognisable.
    std::string prefix = ".";
    prefix += target.filename().string();
    prefix += ".tmp-";
    prefix += std::to_string(::getpid());
    prefix += '-';
    int error = 0;
    for (int attempt = 0; attempt < max_attempts; ++attempt) {
      path_ = folder / (prefix + std::to_string(counter++));
      // 0666 lets the umask decide the permissions, as for any newly created file.
      fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd_ >= 0) return;
      error = errno;
      if (error != EEXIST && error != EINTR) break;
    }
    path_.clear();
    fail(target_, "cannot create a temporary file in '" + folder.string() + "'", error);
  }

  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  ~TemporaryFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!path_.empty()) ::unlink(path_.c_str());
  }

  const fs::path& path() const { return path_; }

  void write_all(std::string_view contents) {
    const char* data = contents.data();
    std::size_t remaining = contents.size();
    while (remaining > 0) {
      const ssize_t written = ::write(fd_, data, remaining);
      if (written < 0) {
        const int error = errno;
        if (error == EINTR) continue;
        fail(target_, "write failed", error);
      }
      data += written;
      remaining -= static_cast<std::size_t>(written);
    }
  }

  // Replacing a file should not silently change who may read it.
  void copy_permissions_of_target() {
    struct stat existing {};
    if (::stat(target_.c_str(), &existing) == 0 && S_ISREG(existing.st_mode)) {
      // Best effort: not being allowed to copy the mode is no reason to lose the result.
      (void)::fchmod(fd_, existing.st_mode & 07777);
    }
  }

  void flush_and_close() {
    // EINVAL: the file system does not support synchronisation; the data is still written.
    if (::fsync(fd_) != 0) {
      const int error = errno;
      if (error != EINVAL) fail(target_, "flushing to disk failed", error);
    }
    const int fd = fd_;
    fd_ = -1;
    // On Linux the descriptor is released even when close() reports EINTR, and fsync has
    // already succeeded, so EINTR loses nothing.
    if (::close(fd) != 0) {
      const int error = errno;
      if (error != EINTR) fail(target_, "closing the file failed", error);
    }
  }

  void rename_over_target() {
    if (::rename(path_.c_str(), target_.c_str()) != 0) {
      const int error = errno;
      fail(target_, "cannot replace the file", error);
    }
    path_.clear();
  }

 private:
  fs::path target_;
  fs::path path_;
  int fd_ = -1;
};

fs::path folder_of(const fs::path& path) {
  if (path.empty() || !path.has_filename()) {
    throw IoError("cannot write '" + path.string() + "': not a file name");
  }
  return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

}  // namespace

struct AtomicFileWriter::Temporary : TemporaryFile {
  using TemporaryFile::TemporaryFile;
};

AtomicFileWriter::AtomicFileWriter(const fs::path& target)
    : target_(target), temporary_(std::make_unique<Temporary>(target, folder_of(target))) {}

AtomicFileWriter::~AtomicFileWriter() = default;

void AtomicFileWriter::append(std::string_view bytes) { temporary_->write_all(bytes); }

const fs::path& AtomicFileWriter::temporary_path() const { return temporary_->path(); }

void AtomicFileWriter::commit() {
  temporary_->copy_permissions_of_target();
  temporary_->flush_and_close();
  temporary_->rename_over_target();
}

void write_file_atomically(const std::filesystem::path& path, const std::string& contents) {
  AtomicFileWriter file(path);
  file.append(contents);
  file.commit();
}

}  // namespace stiffmsa
