// heightmarch trace: one technique on one scene with the CPU packet kernels.
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"

namespace heightmarch::cli {

int trace_command(const std::vector<std::string>& args) {
  std::vector<OptionSpec> specs = trace_option_specs();
  specs.push_back({"isa", true, "scalar, sse4.2, avx2, avx512 or auto (default; or $HEIGHTMARCH_ISA)"});
  specs.push_back({"help", false, "this text"});
  const Options options(args, specs);
  if (options.has("help")) {
    std::printf("usage: heightmarch trace [options]\n%s", usage(specs).c_str());
    return 0;
  }
  const Isa isa = select_isa(options.text("isa", ""));
  const TechniqueParams params = technique_params(options);
  const Scene scene = load_scene(options);
  const ThreadLimit limit(thread_count(options));
  const HitBuffers exact = exact_hits(scene, params);
  const RunResult run = run_cpu(scene, exact, params, isa, limit.threads(), 0.3);
  if (options.has("json"))
    std::fputs(metrics_json(scene, params, run).c_str(), stdout);
  else
    std::fputs(summary_text(scene, params, run).c_str(), stdout);
  if (const auto out = options.get("out")) write_run_outputs(*out, scene, params, run, exact);
  return 0;
}

}  // namespace heightmarch::cli
