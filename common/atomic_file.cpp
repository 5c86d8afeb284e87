#include "common/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "common/error.h"

namespace mopad {

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), tmp_(path_ + ".tmp"), open_(true) {}

AtomicFile::~AtomicFile() { Discard(); }

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : path_(std::move(other.path_)), tmp_(std::move(other.tmp_)), open_(other.open_) {
  other.open_ = false;
}

AtomicFile& AtomicFile::operator=(AtomicFile&& other) noexcept {
  if (this != &other) {
    Discard();
    path_ = std::move(other.path_);
    tmp_ = std::move(other.tmp_);
    open_ = other.open_;
    other.open_ = false;
  }
  return *this;
}

void AtomicFile::Discard() noexcept {
  if (open_) std::remove(tmp_.c_str());
  open_ = false;
}

void AtomicFile::Commit(bool sync) {
  if (!open_) throw std::logic_error(path_ + ": AtomicFile committed twice or moved from");
  if (sync) {
    const int fd = ::open(tmp_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
      throw InputError(path_, std::string("cannot open the file; ") + std::strerror(errno));
    const bool synced = ::fsync(fd) == 0;
    const int err = errno;
    ::close(fd);
    if (!synced) throw InputError(path_, std::string("fsync failed; ") + std::strerror(err));
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw InputError(
        path_, std::string("cannot rename the temporary file over it; ") + std::strerror(errno));
  open_ = false;
}

void WriteWholeFile(const std::string& path, const std::string& bytes, bool sync) {
  AtomicFile file(path);
  const int fd = ::open(file.TempPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(path, std::string("cannot write the file; ") + std::strerror(errno));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;
      ::close(fd);
      throw InputError(path, std::string("write failed; ") + std::strerror(err));
    }
    done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0)
    throw InputError(path, std::string("write failed; ") + std::strerror(errno));
  file.Commit(sync);
}

}  // namespace mopad
