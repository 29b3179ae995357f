// heightmarch suite: the main job. Builds the typed plan (suite_plan.hpp), measures every
// configuration once, and writes the run's files from its rows into a fresh directory:
// measurements.json.gz, bench.json.gz (a run's large files kept compressed: a committed run stays
// within its budget, docs/measurements.md), recommendation.json, the gallery (WebP),
// claims.md/claims.json, and through the report (report_command.hpp) report.md and report.html.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "cli/claims_command.hpp"
#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/gzip.hpp"
#include "cli/plan_options.hpp"
#include "cli/recommend_command.hpp"
#include "cli/report_command.hpp"
#include "cli/run_directory.hpp"
#include "experiment/claims_collector.hpp"
#include "experiment/measurement_session.hpp"
#include "experiment/run_estimate.hpp"
#include "experiment/run_outputs.hpp"
#include "heightmarch/error.hpp"
#include "io/atomic_file.hpp"
#include "io/images.hpp"

namespace heightmarch::cli {
namespace {

namespace fs = std::filesystem;

// A gallery's images as WebP: a fifth of PNG's bytes, the same to the eye (io/images.hpp).
constexpr ImageFormat kGalleryImages = ImageFormat::webp;

struct SuiteOptions {
  PlanOptions plan;
  PlanFilters candidates;  // names, checked against the lists by CLI11, turned into typed values by apply()
  RecommendationTarget target;
  OutOptions out;
  GlOptions gl;
  bool no_glsl = false;
  bool record = false;
  bool dry_run = false;
};

std::vector<std::string> technique_name_list() {
  std::vector<std::string> names;
  for (const TechniqueInfo& t : techniques()) names.emplace_back(t.name);
  return names;
}

std::vector<std::string> isa_name_list() {
  std::vector<std::string> names;
  for (Isa isa : all_isas()) names.push_back(to_string(isa));
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

void add_candidate_options(CLI::App& command, PlanFilters& o) {
  command
      .add_option(
          "--techniques", o.techniques,
          "the candidate techniques, comma-separated (default: all): " + joined(technique_name_list()))
      ->delimiter(',')
      ->check(CLI::IsMember(technique_name_list()));
  command
      .add_option("--layers", o.layers,
                  "the candidate layer specs of the layered techniques, comma-separated: N or A-B "
                  "(default: 4, 8, 10, 16, 32, 64, 8-32; quick: 8, 32, 8-32); the sweeps and GLSL at "
                  "fewer threads take them too")
      ->delimiter(',');
  command
      .add_option("--isas", o.isas,
                  "the ISAs to measure, comma-separated (default: every one the CPU runs; the widest is "
                  "the matrix's): " +
                      joined(isa_name_list()))
      ->delimiter(',')
      ->check(CLI::IsMember(isa_name_list()));
  command
      .add_option("--parts", o.parts,
                  "the parts of the plan to measure, comma-separated (default: all): " + joined(part_names()))
      ->delimiter(',')
      ->check(CLI::IsMember(part_names()));
}

// The name of each heightfield in its gallery images' file names: its label as a plain file name
// (letters, digits, '.', '_', '+' and '-', anything else '_'; at most 80 bytes; never starting
// with '.' or '-'), unique in the run ("-2", "-3" after a taken one). A label is a name, never a
// path: whatever the map's path, its images land in the run's gallery/.
using GalleryNames = std::map<std::string, std::string>;
GalleryNames gallery_names(const std::vector<Configuration>& plan) {
  GalleryNames names;
  std::set<std::string> taken;
  for (const Configuration& c : plan) {
    const std::string label = c.heightfield.label();
    if (names.count(label)) continue;
    std::string name;
    for (char ch : label.substr(0, 80))
      name += std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' || ch == '+' || ch == '-'
                  ? ch
                  : '_';
    if (name.empty() || name[0] == '.' || name[0] == '-') name = "_" + name;
    std::string unique = name;
    for (std::size_t i = 2; taken.count(unique); ++i)
      unique = name + "-" + std::to_string(i);  // ends by taken.size() + 2
    taken.insert(unique);
    names[label] = unique;
  }
  return names;
}

// gallery/<heightfield>-<technique>[-<layers>]: the stem of a gallery row's images.
std::string gallery_stem(const Configuration& c, const GalleryNames& names) {
  const std::string what =
      c.kind == RunKind::exact ? "exact" : to_string(c.params.technique) + "-" + to_string(c.params.layers);
  return "gallery/" + names.at(c.heightfield.label()) + "-" + what;
}

// The render, error map and cost map of a gallery row, and where it has an image error its colour
// difference map (and on the exact row the supersampled reference), as WebP images beside each
// other in gallery/,
// written into a fresh directory of its own (mkdtemp: nothing planted there is written through).
void write_gallery_images(const std::string& dir, const TracedRow& traced, const GalleryNames& names) {
  const std::string stem = dir + "/" + gallery_stem(traced.row.config, names);
  std::string tmp = stem + ".tmp-XXXXXX";
  if (!::mkdtemp(tmp.data()))
    throw std::runtime_error(stem + ": cannot write (" + std::strerror(errno) + ")");
  try {
    write_run_outputs(tmp, traced, kGalleryImages);
    const std::string ext = extension(kGalleryImages);
    fs::rename(tmp + "/render" + ext, stem + "-render" + ext);
    fs::rename(tmp + "/error" + ext, stem + "-error" + ext);
    if (traced.row.samples_known) fs::rename(tmp + "/cost" + ext, stem + "-cost" + ext);
    if (traced.shaded) {
      fs::rename(tmp + "/difference" + ext, stem + "-difference" + ext);
      if (traced.row.config.kind == RunKind::exact)
        fs::rename(tmp + "/reference" + ext, stem + "-reference" + ext);
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(tmp, ignored);  // a full disk leaves no half-written temporary behind
    throw;
  }
  fs::remove_all(tmp);
}

}  // namespace

Command add_suite_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "suite", "the main job: the measured plan, gallery, claims and report into results/");
  auto o = std::make_shared<SuiteOptions>();
  add_plan_options(*command, o->plan,
                   "a smoke run of under a minute on 2 cores: two heightfields, small views");
  add_out_options(*command, o->out, "run directory (default: a fresh results/<date>-<commit>-<time>)");
  command->add_flag("--no-glsl", o->no_glsl, "skip the GLSL rows");
  add_gl_options(*command, o->gl);
  command->add_flag("--record", o->record,
                    "with --quick: still point results/latest at the run and add it to results/history.csv");
  add_candidate_options(*command, o->candidates);
  add_target_options(*command, o->target);
  command->add_flag(
      "--dry-run", o->dry_run,
      "read and check every input as the run would (its one-line errors), list the configurations the run "
      "would measure (heightfield, kind, technique, layers, backend, threads, view, filter (- for the exact "
      "reference and the calibration loop), timed or accuracy only, purposes; tab-separated), estimate the "
      "run's time from a short calibration, and measure and write nothing");
  return [o] {
    PlanSettings settings = plan_settings(o->plan, !o->no_glsl);
    if (settings.glsl) settings.gl = gl_target(o->gl);
    apply(o->candidates, settings);
    validate(o->target);
    const std::vector<Configuration> plan = suite_plan(settings);
    // Every input the run reads, read and checked as the run reads it, before the run directory
    // exists: a dry run fails where the run would, and a run that fails here leaves nothing behind.
    MeasurementSession session;
    const std::vector<ViewRays> views = session.check_inputs(plan);
    if (o->dry_run) {
      for (const Configuration& c : plan) std::printf("%s\n", plan_line(c).c_str());
      std::printf("%zu configurations\n", plan.size());
      std::fflush(stdout);
      const RunEstimate e = estimate_run(plan, views, settings.repetitions, settings.min_seconds, session);
      std::printf(
          "estimated time: about %s to measure (calibrated on %zu configurations at up to %zu rays each "
          "in %.0f s; the report and the gallery of what to ship come after it)\n",
          duration_text(e.seconds).c_str(), e.calibrated, kCalibrationRays, e.calibration_seconds);
      return 0;
    }
    const bool default_out = o->out.out.empty();
    const std::string run_name = fresh_run_name(o->plan.quick);
    RunDirectory dir(default_out ? "results/" + run_name : o->out.out, o->out.existing(), {"gallery"});
    const bool record = default_out && (!o->plan.quick || o->record);
    Progress progress("suite");
    std::size_t timed = 0;
    for (const Configuration& c : plan) timed += c.timed;
    progress.stage("measuring " + std::to_string(plan.size()) + " configurations (" + std::to_string(timed) +
                   " timed, " + std::to_string(settings.repetitions) + " interleaved repetitions each: " +
                   std::to_string(plan_runs(plan, settings.repetitions)) + " runs) into " + dir.path());
    ClaimsCollector claims;
    const GalleryNames names = gallery_names(plan);
    const auto on_traced = [&](const TracedRow& traced) {
      if (traced.row.config.purposes & kPurposeGallery) write_gallery_images(dir.path(), traced, names);
      claims.observe(traced);
    };
    MeasuredPlan run = measure_with_progress(plan, settings, progress, on_traced, session);
    if (run.load.busy)
      for (const std::string& reason : run.load.busy_reasons)
        std::fprintf(stderr, "suite: warning: busy machine: %s\n", reason.c_str());
    const Recommendation recommendation = recommend(candidates(run.rows, o->target.unit), o->target);
    write_recommendation(dir.path(), recommendation);
    dir.finished("recommendation.json");
    // What to ship, seen: the recommended configuration of every map beside its exact render.
    if (settings.parts & kPurposeGallery) {
      const std::vector<Configuration> shown = recommended_gallery_plan(recommendation, settings, plan);
      progress.stage("the gallery of what to ship: " + std::to_string(shown.size()) + " configurations");
      for (Measurement& m : measure_with_progress(shown, settings, progress, on_traced, session).rows) {
        m.id += int(run.rows.size());
        run.rows.push_back(std::move(m));
      }
    }
    for (Measurement& m : run.rows)
      if ((m.config.purposes & kPurposeGallery) && m.failure.empty()) {
        const std::string stem = gallery_stem(m.config, names);
        m.render_image = stem + "-render" + extension(kGalleryImages);
        m.error_image = stem + "-error" + extension(kGalleryImages);
        if (m.samples_known) m.cost_image = stem + "-cost" + extension(kGalleryImages);
        if (m.image_error) {
          m.difference_image = stem + "-difference" + extension(kGalleryImages);
          if (m.config.kind == RunKind::exact)
            m.reference_image = stem + "-reference" + extension(kGalleryImages);
        }
      }
    dir.finished("measurements and gallery images");
    write_file_atomically(dir.path() + "/measurements.json.gz", gzip(measurements_json(run, settings.name)));
    write_file_atomically(dir.path() + "/bench.json.gz", gzip(benchmark_json(run)));
    dir.finished("measurements.json.gz, bench.json.gz");
    if (settings.parts & kPurposeClaims) {
      progress.stage("claims");
      write_claims(dir.path(), claims.data(run.rows), settings, recommendation);
      dir.finished("claims.md, claims.json");
    }
    progress.stage("report");
    write_report(dir.path(), "");
    dir.complete();
    if (record) {  // only a complete run is recorded: the report again, now with the history and its alerts
      progress.stage("recording into results/history.csv");
      write_report(dir.path(), "results/history.csv");
      std::error_code ec;
      fs::remove("results/latest", ec);
      fs::create_directory_symlink(run_name, "results/latest");
    }
    std::fprintf(stderr, "suite: done in %.0f s: %s/report.md\n", progress.total_seconds(),
                 dir.path().c_str());
    if (record) say_signal_after_record("suite", "results/history.csv");
    return 0;
  };
}

}  // namespace heightmarch::cli
