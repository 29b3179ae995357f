#include "cli/options.hpp"

#include <charconv>
#include <cmath>

#include "heightmarch/error.hpp"

namespace heightmarch::cli {

Options::Options(const std::vector<std::string>& args, const std::vector<OptionSpec>& specs) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.rfind("--", 0) != 0 || arg.size() == 2) throw InputError("unexpected argument '" + arg + "'");
    std::string name = arg.substr(2), value;
    const auto equals = name.find('=');
    const bool inline_value = equals != std::string::npos;
    if (inline_value) {
      value = name.substr(equals + 1);
      name = name.substr(0, equals);
    }
    const OptionSpec* spec = nullptr;
    for (const OptionSpec& s : specs)
      if (s.name == name) spec = &s;
    if (!spec) throw InputError("unknown option --" + name + " (see --help)");
    if (spec->takes_value && !inline_value) {
      if (i + 1 >= args.size()) throw InputError("option --" + name + " needs a value");
      value = args[++i];
    } else if (!spec->takes_value && inline_value) {
      throw InputError("option --" + name + " takes no value");
    }
    values_[name] = value;
  }
}

std::optional<std::string> Options::get(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::string Options::text(const std::string& name, const std::string& fallback) const {
  return get(name).value_or(fallback);
}

int Options::integer(const std::string& name, int fallback, int min, int max) const {
  const auto text = get(name);
  if (!text) return fallback;
  long long value = 0;
  const char* end = text->data() + text->size();
  const auto [ptr, ec] = std::from_chars(text->data(), end, value);
  if (text->empty() || ec != std::errc() || ptr != end)
    throw InputError("--" + name + " '" + *text + "' is not a whole number");
  if (value < min || value > max)
    throw InputError("--" + name + " " + *text + " is outside [" + std::to_string(min) + ", " +
                     std::to_string(max) + "]");
  return int(value);
}

double Options::number(const std::string& name, double fallback) const {
  const auto text = get(name);
  if (!text) return fallback;
  double value = 0;
  const char* end = text->data() + text->size();
  const auto [ptr, ec] = std::from_chars(text->data(), end, value);
  if (text->empty() || ec != std::errc() || ptr != end || !std::isfinite(value))
    throw InputError("--" + name + " '" + *text + "' is not a finite number");
  return value;
}

std::string usage(const std::vector<OptionSpec>& specs) {
  std::string text;
  for (const OptionSpec& s : specs) {
    std::string left = "  --" + s.name + (s.takes_value ? " VALUE" : "");
    left.resize(std::max<std::size_t>(left.size() + 2, 30), ' ');
    text += left + s.help + "\n";
  }
  return text;
}

}  // namespace heightmarch::cli
