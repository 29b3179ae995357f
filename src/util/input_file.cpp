#include "util/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "heightmarch/error.hpp"

namespace heightmarch {
namespace {

std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string size_text(std::uintmax_t bytes) {
  if (bytes < (1u << 20)) return std::to_string(bytes) + " bytes";
  return std::to_string(bytes >> 20) + " MiB";
}

std::uintmax_t check_stat(const struct stat& st, const std::string& path, const std::string& what,
                          std::uintmax_t max_bytes) {
  if (!S_ISREG(st.st_mode))
    throw InputError(path + ": is " + kind_of(st.st_mode) + ", not a regular file (" + what + ")");
  const std::uintmax_t size = std::uintmax_t(st.st_size);
  if (size > max_bytes)
    throw InputError(path + ": " + size_text(size) + ", more than the " + size_text(max_bytes) + " a " + what +
                     " may have");
  return size;
}

}  // namespace

std::uintmax_t check_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  return check_stat(st, path, what, max_bytes);
}

std::string read_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  // O_NONBLOCK: opening a FIFO does not wait for a writer; it is refused below.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  struct stat st {};
  std::string text;
  try {
    if (::fstat(fd, &st) != 0) throw InputError(path + ": cannot stat " + what + " (" + std::strerror(errno) + ")");
    text.resize(check_stat(st, path, what, max_bytes));
    std::size_t done = 0;
    // Each pass reads at least one byte, or ends (a file that shrank ends early).
    while (done < text.size()) {
      const ssize_t n = ::read(fd, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw InputError(path + ": cannot read " + what + " (" + std::strerror(errno) + ")");
      if (n == 0) break;
      done += std::size_t(n);
    }
    text.resize(done);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  return text;
}

}  // namespace heightmarch
