#include "util/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "heightmarch/error.hpp"

namespace heightmarch {
namespace {

std::string size_text(std::uintmax_t bytes) {
  if (bytes < (1u << 20)) return std::to_string(bytes) + " bytes";
  return std::to_string(bytes >> 20) + " MiB";
}

std::uintmax_t check_stat(const struct stat& st, const std::string& path, const std::string& what,
                          std::uintmax_t max_bytes) {
  if (!S_ISREG(st.st_mode))
    throw InputError(path + ": is " + file_kind(st.st_mode) + ", not a regular file (" + what + ")");
  const std::uintmax_t size = std::uintmax_t(st.st_size);
  if (size > max_bytes)
    throw InputError(path + ": " + size_text(size) + ", more than the " + size_text(max_bytes) + " a " +
                     what + " may have");
  return size;
}

}  // namespace

std::string file_kind(unsigned mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a link";  // lstat's
  return "a file of another kind";
}

std::uintmax_t check_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  return check_stat(st, path, what, max_bytes);
}

InputFile::InputFile(const std::string& path, const std::string& what, std::uintmax_t max_bytes)
    : path_(path), what_(what) {
  // O_NONBLOCK: opening a FIFO does not wait for a writer; it is refused below.
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw InputError(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  struct stat st {};
  try {
    if (::fstat(fd_, &st) != 0)
      throw InputError(path + ": cannot stat " + what + " (" + std::strerror(errno) + ")");
    size_ = check_stat(st, path, what, max_bytes);
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

InputFile::~InputFile() { ::close(fd_); }

std::size_t InputFile::read(char* data, std::size_t bytes) {
  // Repeats only on EINTR.
  for (;;) {
    const ssize_t n = ::read(fd_, data, bytes);
    if (n >= 0) return std::size_t(n);
    if (errno != EINTR)
      throw InputError(path_ + ": cannot read " + what_ + " (" + std::strerror(errno) + ")");
  }
}

std::string read_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  InputFile file(path, what, max_bytes);
  std::string text(file.size(), '\0');
  std::size_t done = 0;
  // Each pass reads at least one byte, or ends.
  while (done < text.size()) {
    const std::size_t n = file.read(text.data() + done, text.size() - done);
    if (n == 0) break;
    done += n;
  }
  text.resize(done);
  return text;
}

}  // namespace heightmarch
