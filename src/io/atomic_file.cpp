#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace heightmarch {

namespace {

// Removes the temporary and throws "PATH: cannot write (WHY)"; `error` is the errno of the call
// that failed, taken at once (a later call may change errno).
[[noreturn]] void give_up(const std::string& path, const std::string& temporary, int error) {
  ::unlink(temporary.c_str());
  throw std::runtime_error(path + ": cannot write (" + std::strerror(error) + ")");
}

}  // namespace

std::string temporary_path(const std::string& path) { return path + ".tmp-" + std::to_string(::getpid()); }

void write_file_atomically(const std::string& path, const std::string& content) {
  const std::string temporary = temporary_path(path);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(path + ": cannot write (" + std::strerror(errno) + ")");
  std::size_t done = 0;
  // Each pass writes at least one byte or gives up (a full disk is ENOSPC here or at fsync).
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : ENOSPC;
      ::close(fd);
      give_up(path, temporary, error);
    }
    done += std::size_t(n);
  }
  // fsync: a file renamed into place is whole even after a crash of the machine.
  if (::fsync(fd) != 0 && errno != EINVAL) {
    const int error = errno;
    ::close(fd);
    give_up(path, temporary, error);
  }
  if (::close(fd) != 0) give_up(path, temporary, errno);
  if (std::rename(temporary.c_str(), path.c_str()) != 0) give_up(path, temporary, errno);
}

}  // namespace heightmarch
