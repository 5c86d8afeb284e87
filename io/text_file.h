#pragma once
// Whole text files: the one writer that turns an I/O failure into InputError naming the file.

#include <string>

namespace mopad::io {

/// Writes `text` and a final newline to `path` (binary mode: the bytes as given).
void WriteTextFile(const std::string& path, const std::string& text);

/// The whole file's bytes. InputError naming the file when it cannot be read.
std::string ReadTextFile(const std::string& path);

/// Writes `bytes` (as given, no newline added) to `path` so that a process killed at any
/// moment leaves either the old file or the new one, never a part: a temporary file beside it
/// (`path` + ".tmp"), flushed to disk, then renamed over `path`. InputError naming the file on
/// failure.
void WriteFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace mopad::io
