#pragma once
#include <stdexcept>
#include <string>

namespace vocal {

// Thrown for bad input data (files, images, parameters). The message names the input and the
// problem, so callers (tools, nodelets) can print it as it is.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace vocal
