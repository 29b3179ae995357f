#pragma once
// Command-line options: --name value, --name=value and flags; unknown options are errors.
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace heightmarch::cli {

struct OptionSpec {
  std::string name;   // without the leading dashes
  bool takes_value;
  std::string help;
};

class Options {
 public:
  // Throws InputError for unknown options, missing values and stray arguments.
  Options(const std::vector<std::string>& args, const std::vector<OptionSpec>& specs);

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  std::string text(const std::string& name, const std::string& fallback) const;
  int integer(const std::string& name, int fallback, int min, int max) const;
  double number(const std::string& name, double fallback) const;
  std::optional<std::string> get(const std::string& name) const;

 private:
  std::map<std::string, std::string> values_;
};

std::string usage(const std::vector<OptionSpec>& specs);

}  // namespace heightmarch::cli
