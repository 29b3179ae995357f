// heightmarch claims: measures the tutorials' claims C1-C10 and writes claims.md and claims.json.
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/suite_plan.hpp"
#include "heightmarch/claims_measurement.hpp"
#include "heightmarch/trace.hpp"
#include "io/atomic_file.hpp"
#include "io/provenance.hpp"

namespace heightmarch::cli {

void write_claims(const std::string& dir, const SuitePlan& plan, Isa isa, int threads) {
  ClaimsSetup setup;
  setup.heightfields = plan.heightfields;
  setup.resolution = plan.resolution;
  setup.view_size = plan.claims_view_size;
  setup.sweep_size = plan.claims_sweep_size;
  setup.isa = isa;
  setup.progress = [](const std::string& hf) { std::fprintf(stderr, "claims: measuring %s\n", hf.c_str()); };
  const ClaimsData data = measure_claims(setup);
  const std::vector<ClaimResult> results = evaluate_claims(data);
  const Provenance p = provenance();
  const std::string provenance_line = "Measured " + p.date + " on " + p.cpu + " (" + std::to_string(p.cores) +
                                      " cores), ISA " + to_string(isa) + ", " + std::to_string(threads) +
                                      " threads, commit " + p.commit + ", " + p.compiler + ".";
  std::string heightfields;
  for (const auto& hf : plan.heightfields) heightfields += (heightfields.empty() ? "" : ", ") + heightfield_label(hf);
  const std::string configurations =
      "Configurations: heightfields " + heightfields + " (" + std::to_string(plan.resolution) + " x " +
      std::to_string(plan.resolution) + " builtins), scale 0.1, REPEAT; the default view at " +
      std::to_string(plan.claims_view_size) + " x " + std::to_string(plan.claims_view_size) +
      " pixels for every technique at layers 4, 8, 10, 16, 32, 64 and 8-32; sweep views of " +
      std::to_string(plan.claims_sweep_size) + " x " + std::to_string(plan.claims_sweep_size) +
      " rays at 20, 30, 70 and 80 degrees for the parallax claims. Errors are uv errors in texels against the exact "
      "intersection; speeds are rays/s of the CPU packet kernels.";
  std::filesystem::create_directories(dir);
  write_file_atomically(dir + "/claims.md", claims_markdown(results, provenance_line, configurations));
  write_file_atomically(dir + "/claims.json", claims_json(results));
  for (const ClaimResult& r : results)
    std::printf("%-4s %-13s %s\n", r.id.c_str(), to_string(r.verdict).c_str(), r.claim.c_str());
}

int claims_command(const std::vector<std::string>& args) {
  const std::vector<OptionSpec> specs = {
      {"heightmap", true, "extra depth map files, comma-separated, measured beside the builtins"},
      {"quick", false, "fewer heightfields and smaller views (about a minute)"},
      {"out", true, "directory for claims.md and claims.json (default: current directory)"},
      {"threads", true, "worker threads (default: all cores)"},
      {"isa", true, "scalar, sse4.2, avx2, avx512 or auto"},
      {"help", false, "this text"},
  };
  const Options options(args, specs);
  if (options.has("help")) {
    std::printf("usage: heightmarch claims [options]\n%s", usage(specs).c_str());
    return 0;
  }
  const SuitePlan plan = make_suite_plan(options.has("quick"), options.text("heightmap", ""));
  const Isa isa = select_isa(options.text("isa", ""));
  const ThreadLimit limit(thread_count(options));
  write_claims(options.text("out", "."), plan, isa, limit.threads());
  return 0;
}

}  // namespace heightmarch::cli
