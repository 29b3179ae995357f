#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace heightmarch {

namespace {

constexpr std::size_t kBufferBytes = std::size_t(1) << 20;
// Names tried before giving up: 32 random bits each, so a second try is already rare.
constexpr int kNameAttempts = 64;

std::string random_suffix() {
  std::uint32_t bits = 0;
  // getrandom of 4 bytes never blocks once the kernel's pool is ready and never returns short.
  if (::getrandom(&bits, sizeof bits, 0) != sizeof bits)
    throw std::runtime_error(std::string("getrandom: ") + std::strerror(errno));
  char text[16];
  std::snprintf(text, sizeof text, "%08x", bits);
  return text;
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  // Each pass tries a fresh name; only a name taken (EEXIST) tries again.
  for (int attempt = 0; attempt < kNameAttempts && fd_ < 0; ++attempt) {
    temporary_ = path_ + ".tmp-" + random_suffix();
    fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd_ < 0 && errno != EEXIST)
      throw std::runtime_error(path_ + ": cannot write (" + std::strerror(errno) + ")");
  }
  if (fd_ < 0)
    throw std::runtime_error(path_ + ": cannot write (" + std::to_string(kNameAttempts) +
                             " temporary names beside it were all taken)");
  buffer_.reserve(kBufferBytes);
}

AtomicFile::~AtomicFile() {
  if (fd_ < 0) return;
  ::close(fd_);
  ::unlink(temporary_.c_str());
}

// Removes the temporary and throws "PATH: cannot write (WHY)"; `error` is the errno of the call
// that failed, taken at once (a later call may change errno).
void AtomicFile::give_up(int error) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  ::unlink(temporary_.c_str());
  throw std::runtime_error(path_ + ": cannot write (" + std::strerror(error) + ")");
}

void AtomicFile::append(std::string_view text) {
  if (buffer_.size() + text.size() > kBufferBytes) flush();
  if (text.size() >= kBufferBytes) {
    buffer_.assign(text);
    flush();
  } else {
    buffer_.append(text);
  }
}

int AtomicFile::descriptor() {
  flush();
  return fd_;
}

void AtomicFile::flush() {
  std::size_t done = 0;
  // Each pass writes at least one byte or gives up (a full disk is ENOSPC here or at fsync).
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) give_up(n < 0 ? errno : ENOSPC);
    done += std::size_t(n);
  }
  buffer_.clear();
}

void AtomicFile::commit() {
  flush();
  // fsync: a file renamed into place is whole even after a crash of the machine.
  if (::fsync(fd_) != 0 && errno != EINVAL) give_up(errno);
  const int fd = fd_;
  fd_ = -1;  // closed below whatever close says
  if (::close(fd) != 0) give_up(errno);
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) give_up(errno);
}

void write_file_atomically(const std::string& path, const std::string& content) {
  AtomicFile file(path);
  file.append(content);
  file.commit();
}

}  // namespace heightmarch
