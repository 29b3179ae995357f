// heightmarch claims: measures the claims' rows of the plan (the same rows a suite measures for
// them) and writes claims.md, claims.json, measurements.json and recommendation.json.
#include "cli/claims_command.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/plan_options.hpp"
#include "cli/recommend_command.hpp"
#include "cli/run_directory.hpp"
#include "experiment/claims_collector.hpp"
#include "experiment/run_outputs.hpp"
#include "heightmarch/error.hpp"
#include "io/atomic_file.hpp"
#include "io/markdown.hpp"
#include "io/provenance.hpp"
#include "util/string_format.hpp"

namespace heightmarch::cli {

namespace {

// The rows the claims declare on one kind of view, technique by technique: "steep 4, 8, 16;
// relief 8-32 (at 0, 10 deg)".
std::string claim_rows_text(ClaimView view) {
  std::vector<std::pair<Technique, std::vector<std::string>>> by_technique;
  for (const Claim& claim : claims())
    for (const ClaimRow& row : claim.rows) {
      if (row.view != view) continue;
      std::string what = to_string(row.layers);
      if (view == ClaimView::sweep) what += " at " + std::to_string(int(row.theta)) + " deg";
      auto it = std::find_if(by_technique.begin(), by_technique.end(),
                             [&](auto& t) { return t.first == row.technique; });
      if (it == by_technique.end()) it = by_technique.insert(by_technique.end(), {row.technique, {}});
      if (std::find(it->second.begin(), it->second.end(), what) == it->second.end())
        it->second.push_back(what);
    }
  std::string text;
  for (const auto& [technique, specs] : by_technique) {
    text += (text.empty() ? "" : "; ") + to_string(technique);
    for (std::size_t i = 0; i < specs.size(); ++i) text += (i ? ", " : " ") + specs[i];
  }
  return text;
}

}  // namespace

void write_claims(const std::string& dir, const ClaimsData& data, const PlanSettings& settings,
                  const Recommendation& recommendation) {
  const std::vector<ClaimResult> results = evaluate_claims(data);
  const Provenance p = provenance();
  const std::string provenance_line =
      markdown_text("Measured " + p.date + " on " + p.cpu + " (" + std::to_string(p.cores) + " cores), ISA " +
                    to_string(settings.best_isa) + ", " + std::to_string(settings.threads) +
                    " threads, commit " + p.commit + ", " + p.compiler + " (" + p.build_type + ").");
  std::string heightfields, clamped;
  for (const auto& hf : settings.heightfields) {
    heightfields += (heightfields.empty() ? "" : ", ") + markdown_text(hf.label());
    if (hf.reading.wrap == Wrap::clamp) clamped += (clamped.empty() ? "" : ", ") + markdown_text(hf.label());
  }
  const std::string configurations =
      "Configurations: heightfields " + heightfields + " (builtins at " +
      std::to_string(settings.heightfields.front().resolution) + " x " +
      std::to_string(settings.heightfields.front().resolution) + "), scale " +
      string_format("%g", settings.scale) + ", REPEAT" +
      (clamped.empty() ? "" : " (" + clamped + ": CLAMP_TO_EDGE)") + ", " + to_string(settings.filter) +
      " filtering (docs/conventions.md#filters); on the window " + describe(settings.window) +
      " (docs/measures.md#view-sets; the same rows as the report's tables): " +
      claim_rows_text(ClaimView::default_view) + "; on sweep views of " +
      std::to_string(settings.sweep_size) + " x " + std::to_string(settings.sweep_size) + " rays" +
      (settings.window.kind == ViewSpec::Kind::perspective && !settings.window.around ? "" : " seen around") +
      ": " + claim_rows_text(ClaimView::sweep) +
      (settings.large_maps
           ? "; for P2, the builtins at " + std::to_string(kLargeMapSide) + " x " +
                 std::to_string(kLargeMapSide) + " on the window at about " +
                 std::to_string(kLargeMapViewSide) + " x " + std::to_string(kLargeMapViewSide) +
                 " rays: " + claim_rows_text(ClaimView::large_map)
           : std::string()) +
      ". Errors are uv errors in "
      "texels against the exact intersection; sharp depth changes (|grad D| at the exact hit, top decile of "
      "the view's "
      "rays against its bottom half) and thin features (the ray leaves the solid again within 1/8 of the "
      "depth range) "
      "are measured per ray from each depth map, never from its name. Costs are height samples per ray "
      "(deterministic); speeds are rays/s of the CPU packet kernels, the median (min-max) of " +
      std::to_string(settings.repetitions) +
      " interleaved repetitions, shown beside the costs and deciding no verdict but "
      "P2's, a claim about time.";
  write_file_atomically(dir + "/claims.md", claims_markdown(results, provenance_line, configurations,
                                                            recommendation_markdown(recommendation)));
  write_file_atomically(dir + "/claims.json", claims_json(results));
  for (const ClaimResult& r : results)
    std::printf("%-4s %-14s %s\n     %s%s\n", r.id.c_str(), to_string(r.verdict).c_str(), r.claim.c_str(),
                r.summary.c_str(),
                r.previous ? (" (previous rule: " + to_string(r.previous->verdict) + ")").c_str() : "");
}

namespace {

struct ClaimsOptions {
  PlanOptions plan;
  RecommendationTarget target;
  OutOptions out;
  std::string isa;
  bool list = false;
};

}  // namespace

Command add_claims_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "claims", "measure the tutorials' claims C1-C10 and the papers' P1-P3 and write claims.md");
  auto o = std::make_shared<ClaimsOptions>();
  add_plan_options(*command, o->plan, "the quick plan's heightfields and sizes");
  add_out_options(
      *command, o->out,
      "directory for claims.md, claims.json, measurements.json and recommendation.json (default: a "
      "fresh results/<date>-<commit>-<time>-claims)");
  command->add_option("--isa", o->isa, isa_names() + " or auto");
  command->add_flag("--list", o->list,
                    "list the claims (id, words, the rows each reads) and measure nothing");
  add_target_options(*command, o->target);
  return [o] {
    if (o->list) {
      for (const Claim& claim : claims())
        std::printf("%s\t%s\t%zu rows\n", claim.id.c_str(), claim.claim.c_str(), claim.rows.size());
      return 0;
    }
    if (o->plan.filters.size() > 1)
      throw InputError(
          "claims --filter takes one filter: the claims are read under one (suite compares filters)");
    PlanSettings settings = plan_settings(o->plan, false);
    settings.compared_filters.clear();  // the claims' rows are read under the run's one filter
    settings.best_isa = select_isa(o->isa);
    validate(o->target);
    const std::vector<Configuration> plan = with_held_out(claims_plan(settings), settings);
    MeasurementSession session;
    session.check_inputs(plan);  // every input read and checked, before the run directory exists
    // checked and locked before the run
    RunDirectory dir(o->out.out.empty() ? "results/" + fresh_run_name(o->plan.quick, "claims") : o->out.out,
                     o->out.existing());
    Progress progress("claims");
    progress.stage("measuring " + std::to_string(plan.size()) + " configurations on " +
                   std::to_string(settings.heightfields.size()) + " heightfields (" +
                   std::to_string(plan_runs(plan, settings.repetitions)) + " runs) into " + dir.path());
    ClaimsCollector claims;
    const MeasuredPlan run = measure_with_progress(
        plan, settings, progress, [&](const TracedRow& traced) { claims.observe(traced); }, session);
    write_file_atomically(dir.path() + "/measurements.json",
                          measurements_json(run, settings.name + " claims"));
    dir.finished("measurements.json");
    const Recommendation recommendation = recommend(candidates(run.rows, o->target.unit), o->target);
    write_recommendation(dir.path(), recommendation);
    write_claims(dir.path(), claims.data(run.rows), settings, recommendation);
    dir.complete();
    std::fprintf(stderr, "claims: done in %.0f s: %s/claims.md\n", progress.total_seconds(),
                 dir.path().c_str());
    return 0;
  };
}

}  // namespace heightmarch::cli
