// build/heightmarch: subcommand dispatch and the one place where errors become exit codes.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <map>
#include <string>

#include "cli/commands.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/memory_budget.hpp"
#include "io/provenance.hpp"

int main(int argc, char** argv) {
  using namespace heightmarch;
  CLI::App app(
      "heightmarch: parallax-mapping techniques as SIMD packet kernels and as GLSL, measured "
      "against the exact ray/heightfield intersection",
      "heightmarch");
  // The ISAs too: what a run here can measure (scripts/test reads them for its capped phase).
  app.set_version_flag("--version", [] {
    return "heightmarch " HEIGHTMARCH_VERSION " (commit " + provenance().commit + ", " +
           provenance().build_type + ")\nISAs this CPU runs: " + runnable_isa_names();
  });
  app.require_subcommand(1);
  std::map<const CLI::App*, cli::Command> commands;
  std::string memory_limit;
  for (auto add : {cli::add_trace_command, cli::add_suite_command, cli::add_claims_command,
                   cli::add_recommend_command, cli::add_report_command, cli::add_glsl_command}) {
    cli::Command run = add(app);
    CLI::App* command = app.get_subcommands({}).back();
    command->add_option(
        "--memory-limit", memory_limit,
        "the most memory the run may hold, its own code and libraries included (bytes, or with a "
        "suffix K, M, G or T: 512M, 1.5G; default: $HEIGHTMARCH_MEMORY_LIMIT, else half the RAM)");
    commands[command] = std::move(run);
  }
  const auto subcommands = app.get_subcommands({});
  const bool known = argc >= 2 && std::any_of(subcommands.begin(), subcommands.end(),
                                              [&](const CLI::App* c) { return c->get_name() == argv[1]; });
  if (argc >= 2 && argv[1][0] != '-' && !known) {
    std::fprintf(
        stderr,
        "heightmarch: unknown command '%s' (trace, glsl, suite, claims, recommend, report; see --help)\n",
        error_line(argv[1]).c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    if (message.empty() || argc < 2)
      message = "a command is required (trace, glsl, suite, claims, recommend, report; see --help)";
    std::fprintf(stderr, "heightmarch: %s\n", error_line(message).c_str());
    return 2;
  } catch (const InputError& e) {  // --version's ISAs under a malformed HEIGHTMARCH_MAX_ISA
    std::fprintf(stderr, "heightmarch: %s\n", e.what());
    return 2;
  }
  try {
    // The budget before any work: a malformed one, or one below what the program itself holds.
    if (!memory_limit.empty()) set_memory_budget(parse_memory_limit(memory_limit, "--memory-limit"));
    check_memory_budget_covers_footprint("heightmarch");
    return commands.at(app.get_subcommands().front())();
  } catch (const cli::ChildFailed& e) {
    return e.status;
  } catch (const InputError& e) {
    std::fprintf(stderr, "heightmarch: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "heightmarch: out of memory\n");
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heightmarch: %s\n", error_line(e.what()).c_str());
    return 1;
  }
}
