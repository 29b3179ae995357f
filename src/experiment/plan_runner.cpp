// The scheduler of the measurement pass: each scene's configurations once for their accuracy,
// then every timed one in interleaved rounds, with progress and the machine's load.
#include "experiment/plan_runner.hpp"

#include <algorithm>
#include <chrono>

#include "experiment/machine_load.hpp"
#include "experiment/measurement_session.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/tracer.hpp"

namespace heightmarch {
namespace {

using Clock = std::chrono::steady_clock;

class PlanRunner {
 public:
  PlanRunner(const std::vector<Configuration>& plan, const MeasureOptions& options,
             MeasurementSession& session)
      : plan_(plan),
        options_(options),
        session_(session),
        total_steps_(plan_runs(plan, options.repetitions)) {}

  MeasuredPlan run() {
    MeasuredPlan result;
    result.repetitions = options_.repetitions;
    result.min_seconds = options_.min_seconds;
    read_load_average(result.load.before);
    result.rows.resize(plan_.size());
    // Scenes in first-seen order: every configuration on the same heightfield and view.
    std::vector<std::vector<std::size_t>> scenes;
    for (std::size_t i = 0; i < plan_.size(); ++i) {
      auto it = std::find_if(scenes.begin(), scenes.end(), [&](const std::vector<std::size_t>& s) {
        return plan_[s.front()].heightfield == plan_[i].heightfield && plan_[s.front()].view == plan_[i].view;
      });
      if (it == scenes.end())
        scenes.push_back({i});
      else
        it->push_back(i);
    }
    for (const auto& members : scenes) run_scene(members, result.rows);
    read_load_average(result.load.after);
    assess_load(result.load, other_ticks_, timed_seconds_);
    return result;
  }

 private:
  void step(const std::string& what) {
    if (options_.progress) options_.progress(what, ++done_steps_, total_steps_);
  }

  void run_scene(const std::vector<std::size_t>& members, std::vector<Measurement>& rows) {
    for (std::size_t i : members) {
      rows[i] = session_.measure(plan_[i], int(i), options_.on_traced);
      step(describe_row(rows[i]));
    }
    std::vector<std::size_t> timed;
    for (std::size_t i : members)
      if (plan_[i].timed && rows[i].failure.empty()) timed.push_back(i);
    for (int round = 0; round < options_.repetitions; ++round)
      for (std::size_t i : timed) {
        time_repetition(plan_[i], rows[i]);
        step(describe_row(rows[i]) + " (round " + std::to_string(round + 1) + ")");
      }
    session_.forget_scenes();
  }

  static std::string describe_row(const Measurement& m) {
    const Configuration& c = m.config;
    std::string what = c.heightfield.label() + " " + to_string(c.kind);
    if (c.has_technique() || c.shader) what += " " + c.label() + "-" + to_string(c.params.layers);
    return what + " " + c.backend() + " x" + std::to_string(c.threads) + " " + describe(c.view);
  }

  // One repetition: a warm-up trace, then traces until min_seconds have passed; the mean time of
  // one added to the row (for GLSL, the mean of each of the draw's clocks too).
  void time_repetition(const Configuration& c, Measurement& row) {
    const ThreadLimit limit(c.threads);
    const std::function<TraceTime()> once = session_.trace_once(c);
    once();  // warm-up: caches, TBB's workers, llvmpipe's JIT after a prepare
    const bool cpu = c.kind != RunKind::glsl;  // llvmpipe's own threads are not ours to count
    const CpuTicks ticks_before = cpu ? read_cpu_ticks() : CpuTicks{};
    const Clock::time_point start = Clock::now();
    int runs = 0, timer_runs = 0;
    double traced = 0, elapsed = 0, gl_wall = 0, gl_timer = 0;
    constexpr int kMaxRuns = 100000;
    do {
      const TraceTime time = once();
      traced += time.seconds;
      if (time.gl) {
        gl_wall += time.gl->wall_seconds;
        timer_runs += time.gl->timer_seconds.has_value();
        gl_timer += time.gl->timer_seconds.value_or(0.0);
      }
      ++runs;
      elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    } while (elapsed < options_.min_seconds && runs < kMaxRuns);
    if (cpu) {
      const CpuTicks ticks_after = read_cpu_ticks();
      other_ticks_ += std::max(0.0, (ticks_after.machine_busy - ticks_before.machine_busy) -
                                        (ticks_after.self - ticks_before.self));
      timed_seconds_ += elapsed;
    }
    row.seconds.push_back(traced / runs);
    if (c.kind != RunKind::glsl) return;
    row.gl_wall_seconds.push_back(gl_wall / runs);
    if (timer_runs == runs) row.gl_timer_seconds.push_back(gl_timer / runs);  // every draw's, or none
  }

  const std::vector<Configuration>& plan_;
  const MeasureOptions& options_;
  MeasurementSession& session_;
  std::size_t total_steps_, done_steps_ = 0;
  double other_ticks_ = 0, timed_seconds_ = 0;
};

}  // namespace

std::size_t plan_runs(const std::vector<Configuration>& plan, int repetitions) {
  std::size_t runs = 0;
  for (const Configuration& c : plan) runs += 1 + (c.timed ? std::size_t(repetitions) : 0);
  return runs;
}

MeasuredPlan measure_plan(const std::vector<Configuration>& plan, const MeasureOptions& options,
                          MeasurementSession& session) {
  if (options.repetitions < 1 || options.repetitions > 1000)
    throw InputError("repetitions " + std::to_string(options.repetitions) + " outside [1, 1000]");
  if (!(options.min_seconds >= 0.0 && options.min_seconds <= 60.0))
    throw InputError("time per repetition outside [0, 60] s");
  return PlanRunner(plan, options, session).run();
}

MeasuredPlan measure_plan(const std::vector<Configuration>& plan, const MeasureOptions& options) {
  MeasurementSession session;
  return measure_plan(plan, options, session);
}

}  // namespace heightmarch
