// heightmarch trace: one technique (or the exact reference) on one scene with the CPU kernels.
#include <cstdio>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/progress.hpp"
#include "experiment/measurement_session.hpp"
#include "experiment/run_outputs.hpp"
#include "io/atomic_file.hpp"

namespace heightmarch::cli {

Command add_trace_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "trace", "run one technique with the CPU packet kernels and measure it against the exact hits");
  auto options = std::make_shared<TraceOptions>();
  auto isa = std::make_shared<std::string>();
  add_trace_options(*command, *options, true);
  command->add_option("--isa", *isa, isa_names() + " or auto (default: auto, or $HEIGHTMARCH_ISA)");
  return [options, isa] {
    Configuration config =
        trace_configuration(*options, options->technique == "exact" ? RunKind::exact : RunKind::trace);
    config.isa = select_isa(*isa);
    MeasurementSession session;
    session.check_inputs({config});   // its map and rays read and checked before --out is made
    std::optional<RunDirectory> dir;  // checked and locked before the run
    if (!options->out.out.empty()) dir.emplace(options->out.out, options->out.existing());
    MeasureOptions measure;
    measure.repetitions = options->repetitions;
    measure.min_seconds = 0.05;
    if (dir) measure.on_traced = [&](const TracedRow& traced) { write_run_outputs(dir->path(), traced); };
    // On a terminal, a run that takes more than about 2 s shows how far it is; logs stay clean.
    Progress progress("trace");
    if (progress.interactive())
      measure.progress = [&](const std::string& what, std::size_t done, std::size_t total) {
        if (progress.total_seconds() > 2.0) progress.step(what, done, total);
      };
    const MeasuredPlan run = measure_plan({config}, measure, session);
    progress.finish_line();
    const Measurement& row = run.rows.front();
    // metrics.json again, now with the timed repetitions.
    if (dir) {
      write_file_atomically(dir->path() + "/metrics.json", metrics_json(row));
      dir->complete();
    }
    std::fputs((options->json ? metrics_json(row) : summary_text(row)).c_str(), stdout);
    return row.failure.empty() ? 0 : 1;
  };
}

}  // namespace heightmarch::cli
