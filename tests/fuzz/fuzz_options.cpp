// libFuzzer: command lines (NUL-separated arguments) parse into a typed configuration of the
// trace command, or give a CLI11 parse error or an InputError: never a crash or an invalid value.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "cli/common_options.hpp"
#include "heightmarch/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args(1);
  for (std::size_t i = 0; i < size && args.size() < 64; ++i) {
    if (data[i] == 0)
      args.emplace_back();
    else
      args.back() += char(data[i]);
  }
  using namespace heightmarch;
  CLI::App app("fuzz");
  cli::TraceOptions options;
  cli::add_trace_options(app, options, true);
  try {
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 parses a reversed vector
    app.parse(reversed);
    const Configuration c =
        cli::trace_configuration(options, options.technique == "exact" ? RunKind::exact : RunKind::trace);
    if (!(c.params.scale >= 0.0f && c.params.scale <= 1.0f) || !(c.params.light[2] > 0.0f)) __builtin_trap();
    if (c.view.kind == ViewSpec::Kind::sweep &&
        !(c.view.theta_degrees >= 0.0f && c.view.theta_degrees <= 89.0f))
      __builtin_trap();
    if (c.threads < 1) __builtin_trap();
  } catch (const CLI::Error&) {
  } catch (const InputError&) {
  }
  return 0;
}
