#include "common/error.h"

namespace mopad {

std::string FormatError(const std::string& where, const std::string& what, const std::string& got,
                        const std::string& expected) {
  std::string m;
  if (!where.empty()) m += where + ": ";
  m += "error: " + what;
  if (!got.empty()) m += "; got " + got;
  if (!expected.empty()) m += (got.empty() ? "; expected " : ", expected ") + expected;
  // One line, always: collapse embedded newlines from third-party messages.
  for (char& c : m)
    if (c == '\n' || c == '\r') c = ' ';
  return m;
}

InputError::InputError(const std::string& where, const std::string& what, const std::string& got,
                       const std::string& expected)
    : std::runtime_error(FormatError(where, what, got, expected)) {}

InputError::InputError(const std::string& full_message) : std::runtime_error(full_message) {}

}  // namespace mopad
