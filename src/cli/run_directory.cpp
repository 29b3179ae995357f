#include "cli/run_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <ctime>
#include <filesystem>

#include "heightmarch/error.hpp"
#include "io/atomic_file.hpp"
#include "io/provenance.hpp"

namespace heightmarch::cli {

namespace fs = std::filesystem;

RunDirectory::RunDirectory(std::string path) : path_(std::move(path)) {
  std::error_code ec;
  fs::create_directories(path_, ec);
  if (ec) throw InputError(path_ + ": cannot create the run directory (" + ec.message() + ")");
  lock_fd_ = ::open((path_ + "/.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw InputError(path_ + ": cannot create its lock file");
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw InputError(path_ + ": another run is writing into this directory (it holds " + path_ + "/.lock)");
  }
  for (const char* file : {"measurements.json", "INCOMPLETE"})
    if (fs::exists(path_ + "/" + file)) {
      ::close(lock_fd_);
      lock_fd_ = -1;
      throw InputError(path_ + ": already holds a run (" + file + "); choose another --out or remove it");
    }
  finished("");
}

RunDirectory::~RunDirectory() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the lock; an interrupted run keeps INCOMPLETE
}

void RunDirectory::finished(const std::string& stage) {
  if (!stage.empty()) finished_ += "- " + stage + "\n";
  write_file_atomically(path_ + "/INCOMPLETE", "This run did not complete. Finished stages:\n" + finished_);
}

void RunDirectory::complete() {
  std::error_code ec;
  fs::remove(path_ + "/INCOMPLETE", ec);
}

std::string fresh_run_name(bool quick) {
  const Provenance p = provenance();
  const std::time_t now = std::time(nullptr);
  char time[16];
  std::strftime(time, sizeof time, "%H%M%S", std::gmtime(&now));
  return p.date.substr(0, 10) + "-" + p.commit + "-" + time + (quick ? "-quick" : "");
}

}  // namespace heightmarch::cli
