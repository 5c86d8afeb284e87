#pragma once
// Whole text files: the one writer that turns an I/O failure into InputError naming the file.

#include <string>

namespace mopad::io {

/// Writes `text` and a final newline to `path` (binary mode: the bytes as given).
void WriteTextFile(const std::string& path, const std::string& text);

}  // namespace mopad::io
