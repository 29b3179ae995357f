#pragma once
// Errors caused by the user's input (files, options). The CLI prints them as one line and exits 2.
#include <stdexcept>
#include <string>

namespace heightmarch {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace heightmarch
