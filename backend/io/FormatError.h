#pragma once

#include <stdexcept>

namespace ambler::io {

// A file that cannot be used as asked: missing, truncated, malformed or
// inconsistent. what() names the file and the problem, for the operator.
class FormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ambler::io
