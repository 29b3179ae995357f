#pragma once
// The values of a list option (--techniques, --layers, --filter, --threads, ...) once typed: a value
// given twice is refused in one line, never measured twice nor dropped without a word.
#include <cstddef>
#include <string>
#include <vector>

#include "heightmarch/error.hpp"

namespace heightmarch {

// Throws InputError "OPTION: SHOWN is given twice" for the first value equal to one before it;
// shown(value) writes a value as the user would.
template <class T, class Shown>
void refuse_repeats(const std::vector<T>& values, const std::string& option, const Shown& shown) {
  for (std::size_t i = 0; i < values.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (values[j] == values[i]) throw InputError(option + ": " + shown(values[i]) + " is given twice");
}

}  // namespace heightmarch
