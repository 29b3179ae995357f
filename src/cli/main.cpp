// build/heightmarch: subcommand dispatch and the one place where errors become exit codes.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "heightmarch/error.hpp"

namespace {

constexpr const char* kUsage =
    "usage: heightmarch COMMAND [options]\n"
    "  trace   run one technique with the CPU packet kernels and measure it against the exact hits\n"
    "  suite   the main job: benchmark matrix, error sweeps, gallery, claims and report into results/\n"
    "  claims  measure the tutorials' claims C1-C10 and write claims.md\n"
    "  glsl    run the same technique as GLSL in OSMesa (llvmpipe); --compare sets it beside the CPU\n"
    "run 'heightmarch COMMAND --help' for its options\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace heightmarch;
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  try {
    if (command == "trace") return cli::trace_command(args);
    if (command == "glsl") return cli::glsl_command(args);
    if (command == "suite") return cli::suite_command(args);
    if (command == "claims") return cli::claims_command(args);
    if (command == "--help" || command == "help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    std::fprintf(stderr, "heightmarch: unknown command '%s' (run 'heightmarch --help')\n", command.c_str());
    return 2;
  } catch (const InputError& e) {
    std::fprintf(stderr, "heightmarch: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "heightmarch: out of memory\n");
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heightmarch: %s\n", e.what());
    return 1;
  }
}
