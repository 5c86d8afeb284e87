#include "io/text_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "common/error.h"

namespace mopad::io {

void WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot write the file");
  f << text << "\n";
  if (!f) throw InputError(path, "write failed");
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot read the file");
  std::string s((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) throw InputError(path, "read failed");
  return s;
}

void WriteFileAtomically(const std::string& path, const std::string& bytes) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(tmp, std::string("cannot write the file; ") + std::strerror(errno));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = errno;
      ::close(fd);
      throw InputError(tmp, std::string("write failed; ") + std::strerror(err));
    }
    done += static_cast<std::size_t>(n);
  }
  // The data reaches the disk before the rename makes it the file (a power cut, not only a
  // killed process, then leaves the old or the new file).
  const bool synced = ::fsync(fd) == 0;
  const int err = errno;
  ::close(fd);
  if (!synced) throw InputError(tmp, std::string("fsync failed; ") + std::strerror(err));
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw InputError(
        path, std::string("cannot rename the temporary file over it; ") + std::strerror(errno));
}

}  // namespace mopad::io
