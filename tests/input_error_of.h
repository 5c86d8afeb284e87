#pragma once
// The message of the InputError `f` throws: how tests pin a clear error for bad input.

#include <functional>
#include <string>

#include "common/error.h"

namespace mopad::test_support {

/// What `f` threw as InputError (its what()), or "" when it threw none.
inline std::string InputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace mopad::test_support
