#pragma once
// An option whose text becomes its typed value where it is read (the programs' edge): parse(text)
// gives the value, and its InputError is the option's one error line ("--views: unknown view set
// 'x' (...)"). Header-only: heightmarch-bench declares such options too.
#include <CLI/CLI.hpp>
#include <string>

#include "heightmarch/error.hpp"

namespace heightmarch::cli {

template <class T, class Parse>
CLI::Option* add_typed_option(CLI::App& app, const std::string& name, T& value, Parse parse,
                              const std::string& help) {
  CLI::Option* option = app.add_option_function<std::string>(
      name, [&value, parse](const std::string& text) { value = parse(text); }, help);
  option->check(CLI::Validator(
      [parse](std::string& text) -> std::string {
        try {
          parse(text);
          return {};
        } catch (const InputError& e) {
          return e.what();
        }
      },
      ""));
  return option;
}

}  // namespace heightmarch::cli
