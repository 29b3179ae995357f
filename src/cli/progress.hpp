#pragma once
// Progress of a long run: on a terminal, one updating line (what runs, how many of the plan's runs
// are done (plan_runs: the stage's header names that total), time left); a line per tenth
// otherwise (CI, logs). What runs is named from the user's files: printable().
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "heightmarch/error.hpp"

namespace heightmarch::cli {

// "45 s", "12 min", "2.3 h": a duration as a person reads it.
inline std::string duration_text(double seconds) {
  char text[32];
  if (seconds < 90)
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  else if (seconds < 90 * 60)
    std::snprintf(text, sizeof text, "%.0f min", seconds / 60);
  else
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600);
  return text;
}

class Progress {
 public:
  explicit Progress(std::string name)
      : name_(std::move(name)), interactive_(isatty(2) && !std::getenv("CI")), start_(Clock::now()) {}

  void stage(const std::string& what) {
    finish_line();
    stage_start_ = Clock::now();
    std::fprintf(stderr, "%s: %s (%.0f s elapsed)\n", name_.c_str(), printable(what).c_str(),
                 seconds_since(start_));
  }

  void step(const std::string& what, std::size_t done, std::size_t total) {
    if (total == 0) return;
    const double seconds = seconds_since(stage_start_);
    const double left = done ? seconds / double(done) * double(total - done) : 0.0;
    if (interactive_) {
      std::fprintf(stderr, "\r\033[K  [%zu/%zu runs] %.0f s left  %s", done, total, left,
                   printable(what.substr(0, 85)).c_str());
      std::fflush(stderr);
      pending_line_ = true;
    } else if (done * 10 / total != (done - 1) * 10 / total) {  // every tenth
      std::fprintf(stderr, "  %zu/%zu runs done, %.0f s left\n", done, total, left);
    }
  }

  void finish_line() {
    if (pending_line_) std::fprintf(stderr, "\n");
    pending_line_ = false;
  }

  double total_seconds() const { return seconds_since(start_); }
  bool interactive() const { return interactive_; }

 private:
  using Clock = std::chrono::steady_clock;
  static double seconds_since(Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
  }
  std::string name_;
  bool interactive_;
  bool pending_line_ = false;
  Clock::time_point start_, stage_start_ = Clock::now();
};

}  // namespace heightmarch::cli
