#pragma once
// How busy the machine is while the measurement pass times CPU work, from /proc.
#include <string>
#include <vector>

namespace heightmarch {

// How busy the machine was while the pass timed CPU work.
struct MachineLoad {
  double before[3] = {0, 0, 0}, after[3] = {0, 0, 0};  // 1, 5, 15 minute load averages
  double other_cpu_share = 0;  // share of all cores' time used by other processes while timing
  bool busy = false;
  std::vector<std::string> busy_reasons;
};

// CPU time of the whole machine and of this process, in clock ticks.
struct CpuTicks {
  double machine_busy = 0, self = 0;
};
CpuTicks read_cpu_ticks();

// The 1, 5 and 15 minute load averages.
void read_load_average(double (&load)[3]);

// Fills load's share of other processes and its verdict: busy when other processes used more
// than 10% of the machine's CPU time while CPU work was timed (other_ticks over timed_seconds),
// or when the 1-minute load average was above half the cores before the run.
void assess_load(MachineLoad& load, double other_ticks, double timed_seconds);

}  // namespace heightmarch
