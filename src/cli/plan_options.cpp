#include "cli/plan_options.hpp"

#include <algorithm>
#include <sstream>

#include "cli/common_options.hpp"
#include "heightmarch/error.hpp"
#include "util/repeats.hpp"

namespace heightmarch::cli {

void add_plan_options(CLI::App& command, PlanOptions& o, const std::string& quick_help) {
  command.add_flag("--quick", o.quick, quick_help);
  command.add_option(
      "--heightmap", o.heightmap,
      std::string("depth map files, comma-separated, measured beside the builtins; each may carry its "
                  "own ") +
          kMapEntryOptionsHelp);
  add_map_options(command, o.map, "every --heightmap file");
  for (const char* option : {"--convention", "--channel", "--wrap", "--allow-flat"})
    command.get_option(option)->needs(command.get_option("--heightmap"));
  command
      .add_flag("--no-builtins", o.no_builtins,
                "measure the --heightmap files alone, without the builtin heightfields")
      ->needs(command.get_option("--heightmap"));
  command
      .add_option("--threads", o.threads,
                  "thread counts, comma-separated (0: all cores; default: 1 and all cores)")
      ->delimiter(',')
      ->check(in_range(0, 1024));
  command
      .add_option("--repetitions", o.repetitions,
                  "timed repetitions per configuration (at least 5 for published figures)")
      ->check(in_range(1, 1000))
      ->capture_default_str();
  command.add_option("--scale", o.scale, "height scale s of every configuration (default 0.1)")
      ->check(in_range(0, 1, true));
  command.add_option(
      "--view-angles", o.view_angles,
      "NEAR-FAR: the view angles from the normal, in degrees, that the default view spans from its near "
      "edge to its far edge (default 30-80); the sweeps cover the same span");
  command
      .add_option(
          "--filter", o.filters,
          "the filter the run's figures are read with: bilinear (level 0; the default) or trilinear (the "
          "mip chain, as shipped shaders read it; the default of --views tutorial, as the tutorial reads "
          "it); suite: a second, comma-separated, adds the technique x layers matrix under it, timed, "
          "with a recommendation of its own beside the first's (the full suite's default: "
          "bilinear,trilinear; "
          "--filter bilinear measures one)")
      ->delimiter(',')
      ->check(CLI::IsMember(filter_names()));
  add_views_option(command, o.views, "around");
}

PlanSettings plan_settings(const PlanOptions& o, bool glsl) {
  refuse_repeats(o.threads, "--threads", [](int t) { return std::to_string(t); });
  std::vector<int> threads;
  for (int t : o.threads) threads.push_back(resolve_threads(t));
  std::sort(threads.begin(), threads.end());
  threads.erase(std::unique(threads.begin(), threads.end()), threads.end());
  PlanSettings settings = suite_settings(o.quick, threads.empty() ? resolve_threads(0) : threads.back());
  if (!threads.empty()) settings.thread_counts = threads;
  if (o.no_builtins) settings.heightfields.clear();
  std::vector<HeightfieldSource> given;
  std::stringstream in(o.heightmap);
  for (std::string path; std::getline(in, path, ',');)
    if (!path.empty()) given.push_back(parse_heightfield(path, 512, 1, map_reading(o.map)));
  refuse_repeats(given, "--heightmap", [](const HeightfieldSource& h) { return h.describe(); });
  for (const HeightfieldSource& h : given) {
    if (std::find(settings.heightfields.begin(), settings.heightfields.end(), h) !=
        settings.heightfields.end())
      throw InputError("--heightmap: " + h.describe() +
                       " is one of the builtins the run measures already (--no-builtins measures the given "
                       "maps alone)");
    settings.heightfields.push_back(h);
  }
  if (settings.heightfields.empty()) throw InputError("--heightmap '" + o.heightmap + "' names no depth map");
  give_unique_labels(settings.heightfields);  // one label per map in every result
  if (o.scale) settings.scale = float(*o.scale);
  if (!o.view_angles.empty()) {
    parse_view_angles(o.view_angles, settings.window);
    settings.sweep_angles = sweep_angles(settings.window.near_degrees, settings.window.far_degrees);
  }
  // The window holds as many rays as the plan's frame, whichever it is.
  const double rays = double(settings.window.width) * settings.window.height;
  const ViewSet views = o.views.value_or(ViewSet::around());
  settings.window = seen_as(settings.window, views);
  size_views_for_rays(settings.window, rays);
  // The tutorial's scene is read as the tutorial reads its depth map, unless asked otherwise.
  // Filters asked for replace the plan's (its first the run's own, the others compared).
  std::vector<Filter> filters;
  for (const std::string& name : o.filters) filters.push_back(parse_filter(name));
  refuse_repeats(filters, "--filter", [](Filter f) { return to_string(f); });
  if (!filters.empty()) {
    settings.filter = filters.front();
    settings.compared_filters.clear();
  } else if (views.kind == ViewSet::Kind::tutorial) {
    settings.filter = Filter::trilinear;
    for (Filter& compared : settings.compared_filters) compared = Filter::bilinear;
  }
  for (const Filter filter : filters) {
    if (filter != settings.filter &&
        std::find(settings.compared_filters.begin(), settings.compared_filters.end(), filter) ==
            settings.compared_filters.end())
      settings.compared_filters.push_back(filter);
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
  measure.progress = [&](const std::string& what, std::size_t done, std::size_t total) {
    progress.step(what, done, total);
  };
  MeasuredPlan run = measure_plan(plan, measure, session);
  progress.finish_line();
  return run;
}

MeasuredPlan measure_with_progress(const std::vector<Configuration>& plan, const PlanSettings& settings,
                                   Progress& progress,
                                   const std::function<void(const TracedRow&)>& on_traced) {
  MeasurementSession session;
  return measure_with_progress(plan, settings, progress, on_traced, session);
}

}  // namespace heightmarch::cli
