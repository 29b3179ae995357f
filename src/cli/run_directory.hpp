#pragma once
// A run's directory: fresh for every run, locked while the run writes into it, and marked
// INCOMPLETE (listing the finished stages) until the run completes.
#include <string>

namespace heightmarch::cli {

class RunDirectory {
 public:
  // Creates and locks path. Throws InputError when another run holds its lock, or when the
  // directory already holds a run (measurements.json or INCOMPLETE).
  explicit RunDirectory(std::string path);
  ~RunDirectory();
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  const std::string& path() const { return path_; }
  void finished(const std::string& stage);  // listed in INCOMPLETE
  void complete();                          // removes INCOMPLETE

 private:
  std::string path_;
  std::string finished_;
  int lock_fd_ = -1;
};

// results/<UTC date>-<commit>-<HHMMSS>[-quick]: unique per run of a commit.
std::string fresh_run_name(bool quick);

}  // namespace heightmarch::cli
