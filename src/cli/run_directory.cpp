#include "cli/run_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <exception>
#include <filesystem>

#include "heightmarch/error.hpp"
#include "io/atomic_file.hpp"
#include "io/provenance.hpp"
#include "util/input_file.hpp"

namespace heightmarch::cli {

namespace fs = std::filesystem;

namespace {

// The files a command writes at the top of its directory: trace and glsl (metrics.json and the
// images), claims (claims.md, claims.json, measurements.json, recommendation.json), suite (all of these but
// trace's, measurements.json.gz, bench.json.gz, report.md) and the marker of a run under way. Any of them
// means the directory holds a run's results. Not rays.csv: a name the user's own rays file may have (trace
// --rays rewrites it whole).
const char* const kRunFiles[] = {
    "INCOMPLETE", "measurements.json",   "measurements.json.gz", "metrics.json",  "claims.json",
    "claims.md",  "recommendation.json", "bench.json",           "bench.json.gz", "report.md",
    "hits.exr",   "error.png",           "render.png",           "cost.png"};

}  // namespace

RunDirectory::RunDirectory(std::string path, Existing existing,
                           const std::vector<std::string>& subdirectories)
    : path_(std::move(path)), exceptions_(std::uncaught_exceptions()) {
  std::error_code ec;
  made_ = fs::create_directories(path_, ec);
  struct stat st {};
  if (::stat(path_.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
    throw InputError(path_ + ": is " + file_kind(st.st_mode) + ", not a directory for the run's results");
  if (ec) throw InputError(path_ + ": cannot create the directory (" + ec.message() + ")");
  // O_NOFOLLOW: a link planted at .lock is refused, never opened (nor created through).
  lock_fd_ = ::open((path_ + "/.lock").c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (lock_fd_ < 0)
    throw InputError(path_ + ": cannot write into it (its .lock: " + std::strerror(errno) + ")");
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw InputError(path_ + ": another run is writing into this directory (it holds " + path_ + "/.lock)");
  }
  if (existing == Existing::beside) return;  // the run's files stay, and no INCOMPLETE is put on it
  for (const char* file : kRunFiles) {
    const std::string at = path_ + "/" + file;
    if (!fs::exists(fs::symlink_status(at, ec))) continue;  // a link counts, dangling or not
    if (existing == Existing::replace) {
      if (::unlink(at.c_str()) == 0 || errno == ENOENT) continue;  // unlink: a link goes, not its target
      const std::string why = std::strerror(errno);
      ::close(lock_fd_);
      lock_fd_ = -1;
      throw InputError(at + ": cannot replace it (" + why + ")");
    }
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw InputError(path_ + ": already holds a run's results (" + file +
                     "); choose another --out, or --replace to replace them");
  }
  for (const std::string& name : subdirectories) {
    const std::string at = path_ + "/" + name;
    struct stat sub {};
    const bool made = ::mkdir(at.c_str(), 0755) == 0;
    if (made) made_subdirectories_.push_back(name);
    const bool there = (made || errno == EEXIST) && ::lstat(at.c_str(), &sub) == 0;
    if (!there || !S_ISDIR(sub.st_mode)) {
      const std::string why = there ? "is " + file_kind(sub.st_mode)
                                    : std::string("cannot create it (") + std::strerror(errno) + ")";
      ::close(lock_fd_);
      lock_fd_ = -1;
      throw InputError(at + ": " + why + ", not a directory of the run's own to write into");
    }
  }
  finished("");
}

RunDirectory::~RunDirectory() {
  if (lock_fd_ < 0) return;
  if (std::uncaught_exceptions() > exceptions_ && !completed_ && holds_nothing_written()) {
    for (const std::string& sub : made_subdirectories_) ::rmdir((path_ + "/" + sub).c_str());
    ::unlink((path_ + "/INCOMPLETE").c_str());
    ::unlink((path_ + "/.lock").c_str());
    if (made_) ::rmdir(path_.c_str());
  }
  ::close(lock_fd_);  // releases the lock; an interrupted run keeps INCOMPLETE
}

bool RunDirectory::holds_nothing_written() const {
  if (!finished_.empty()) return false;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(path_, ec)) {
    const std::string name = entry.path().filename().string();
    const bool made = std::find(made_subdirectories_.begin(), made_subdirectories_.end(), name) !=
                      made_subdirectories_.end();
    if (name == "INCOMPLETE" || name == ".lock" || (made && fs::is_empty(entry.path(), ec) && !ec)) continue;
    return false;
  }
  return !ec;
}

void RunDirectory::finished(const std::string& stage) {
  if (!stage.empty()) finished_ += "- " + stage + "\n";
  write_file_atomically(path_ + "/INCOMPLETE", "This run did not complete. Finished stages:\n" + finished_);
}

void RunDirectory::complete() {
  std::error_code ec;
  fs::remove(path_ + "/INCOMPLETE", ec);
  completed_ = true;
}

std::string fresh_run_name(bool quick, const std::string& kind) {
  const Provenance p = provenance();
  const std::time_t now = std::time(nullptr);
  char time[16];
  std::strftime(time, sizeof time, "%H%M%S", std::gmtime(&now));
  return p.date.substr(0, 10) + "-" + p.commit + "-" + time + (kind.empty() ? "" : "-" + kind) +
         (quick ? "-quick" : "");
}

}  // namespace heightmarch::cli
