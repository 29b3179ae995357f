// libFuzzer: command lines (NUL-separated arguments) parse into technique parameters and a view,
// or give an InputError: never a crash or an invalid value.
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
  try {
    const cli::Options options(args, cli::trace_option_specs());
    const TechniqueParams params = cli::technique_params(options);
    if (!(params.scale >= 0.0f && params.scale <= 1.0f) || !(params.light[2] > 0.0f)) __builtin_trap();
    const ViewSpec view = parse_view(options.text("view", "default"), 8, 8);
    if (!(view.theta_degrees >= 0.0f && view.theta_degrees <= 89.0f)) __builtin_trap();
  } catch (const InputError&) {
  }
  return 0;
}
