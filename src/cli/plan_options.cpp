#include "cli/plan_options.hpp"

#include <algorithm>
#include <sstream>

#include "cli/common_options.hpp"
#include "heightmarch/error.hpp"

namespace heightmarch::cli {

void add_plan_options(CLI::App& command, PlanOptions& o, const std::string& quick_help) {
  command.add_flag("--quick", o.quick, quick_help);
  command.add_option("--heightmap", o.heightmap,
                     "depth map files, comma-separated, measured beside the builtins");
  command
      .add_flag("--no-builtins", o.no_builtins,
                "measure the --heightmap files alone, without the builtin heightfields")
      ->needs(command.get_option("--heightmap"));
  command
      .add_option("--threads", o.threads,
                  "thread counts, comma-separated (0: all cores; default: 1 and all cores)")
      ->delimiter(',')
      ->check(CLI::Range(0, 1024));
  command.add_option("--repetitions", o.repetitions, "timed repetitions per configuration (at least 5 for published figures)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command.add_option("--scale", o.scale, "height scale s of every configuration, in (0, 1] (default 0.1)");
  command.add_option(
      "--view-angles", o.view_angles,
      "NEAR-FAR: the view angles from the normal, in degrees, that the default view spans from its near "
      "edge to its far edge (default 30-80); the sweeps cover the same span");
}

PlanSettings plan_settings(const PlanOptions& o, bool glsl) {
  std::vector<int> threads;
  for (int t : o.threads) threads.push_back(resolve_threads(t));
  std::sort(threads.begin(), threads.end());
  threads.erase(std::unique(threads.begin(), threads.end()), threads.end());
  PlanSettings settings = suite_settings(o.quick, threads.empty() ? resolve_threads(0) : threads.back());
  if (!threads.empty()) settings.thread_counts = threads;
  if (o.no_builtins) settings.heightfields.clear();
  std::stringstream in(o.heightmap);
  for (std::string path; std::getline(in, path, ',');)
    if (!path.empty()) settings.heightfields.push_back(parse_heightfield(path));
  if (settings.heightfields.empty()) throw InputError("--heightmap '" + o.heightmap + "' names no depth map");
  give_unique_labels(settings.heightfields);  // one label per map in every result
  if (o.scale) {
    if (!(*o.scale > 0 && *o.scale <= 1))
      throw InputError("--scale " + std::to_string(*o.scale) + " must be in (0, 1]");
    settings.scale = float(*o.scale);
  }
  if (!o.view_angles.empty()) {
    ViewSpec view;
    parse_view_angles(o.view_angles, view);
    settings.near_degrees = view.near_degrees;
    settings.far_degrees = view.far_degrees;
    settings.sweep_angles = sweep_angles(view.near_degrees, view.far_degrees);
  }
  settings.glsl = glsl;
  settings.repetitions = o.repetitions;
  return settings;
}

MeasuredPlan measure_with_progress(const std::vector<Configuration>& plan, const PlanSettings& settings,
                                   Progress& progress, const std::function<void(const TracedRow&)>& on_traced,
                                   MeasurementSession& session) {
  MeasureOptions measure;
  measure.repetitions = settings.repetitions;
  measure.min_seconds = settings.min_seconds;
  measure.on_traced = on_traced;
  measure.progress = [&](const std::string& what, std::size_t done, std::size_t total) { progress.step(what, done, total); };
  MeasuredPlan run = measure_plan(plan, measure, session);
  progress.finish_line();
  return run;
}

MeasuredPlan measure_with_progress(const std::vector<Configuration>& plan, const PlanSettings& settings,
                                   Progress& progress, const std::function<void(const TracedRow&)>& on_traced) {
  MeasurementSession session;
  return measure_with_progress(plan, settings, progress, on_traced, session);
}

}  // namespace heightmarch::cli
