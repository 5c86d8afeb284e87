#pragma once
// The one error type for bad input (files, YAML, CLI arguments, impossible parameters).
// Its message reads `path:line: error: what; got X, expected Y` so that editors and CI logs
// can jump to the place. Internal invariants use assert, not this type.

#include <stdexcept>
#include <string>

namespace mopad {

class InputError : public std::runtime_error {
 public:
  /// `where` is "path" or "path:line" (may be empty); `got`/`expected` may be empty.
  InputError(const std::string& where, const std::string& what, const std::string& got = "",
             const std::string& expected = "");
  explicit InputError(const std::string& full_message);
};

/// Formats `where: error: what; got X, expected Y` (parts that are empty are left out).
std::string FormatError(const std::string& where, const std::string& what, const std::string& got,
                        const std::string& expected);

}  // namespace mopad
