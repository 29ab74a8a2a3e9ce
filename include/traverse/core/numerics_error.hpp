#pragma once
// The error of a run whose numerics failed (exit code 3): the message says where and why.
#include <stdexcept>

namespace traverse {

class NumericsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace traverse
