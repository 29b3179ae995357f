#include "experiment/machine_load.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace heightmarch {

CpuTicks read_cpu_ticks() {
  CpuTicks ticks;
  std::ifstream stat("/proc/stat");
  std::string cpu;
  double user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
  if (stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal)
    ticks.machine_busy = user + nice + system + irq + softirq + steal;
  std::ifstream self("/proc/self/stat");
  std::string line;
  std::getline(self, line);
  // Fields after the command name (which may hold spaces) start at the last ')'.
  const auto close = line.rfind(')');
  if (close != std::string::npos) {
    std::istringstream rest(line.substr(close + 2));
    std::string field;
    double utime = 0, stime = 0;
    for (int i = 3; i <= 15 && rest >> field; ++i) {
      if (i == 14) utime = std::atof(field.c_str());
      if (i == 15) stime = std::atof(field.c_str());
    }
    ticks.self = utime + stime;
  }
  return ticks;
}

void read_load_average(double (&load)[3]) {
  std::ifstream in("/proc/loadavg");
  in >> load[0] >> load[1] >> load[2];
}

void assess_load(MachineLoad& load, double other_ticks, double timed_seconds) {
  const double ticks_per_second = double(sysconf(_SC_CLK_TCK));
  const double cores = std::max(1u, std::thread::hardware_concurrency());
  load.other_cpu_share = timed_seconds > 0 ? other_ticks / ticks_per_second / (timed_seconds * cores) : 0.0;
  char buf[160];
  if (load.other_cpu_share > 0.10) {
    std::snprintf(buf, sizeof buf,
                  "other processes used %.0f%% of the machine's CPU time while CPU work was timed",
                  100 * load.other_cpu_share);
    load.busy_reasons.push_back(buf);
  }
  if (load.before[0] > 0.5 * cores) {
    std::snprintf(buf, sizeof buf, "the 1-minute load average was %.2f on %g cores before the run",
                  load.before[0], cores);
    load.busy_reasons.push_back(buf);
  }
  load.busy = !load.busy_reasons.empty();
}

}  // namespace heightmarch
