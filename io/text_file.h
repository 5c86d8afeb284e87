#pragma once
// Whole text files: the one writer that turns an I/O failure into InputError naming the file.
// Every file appears whole or not at all (common/atomic_file.h).

#include <string>

namespace mopad::io {

/// Writes `text` and a final newline to `path` (the bytes as given), whole or not at all.
void WriteTextFile(const std::string& path, const std::string& text);

/// The whole file's bytes. InputError naming the file when it cannot be read.
std::string ReadTextFile(const std::string& path);

/// Writes `bytes` (as given, no newline added) to `path` so that a process killed at any
/// moment, or a power cut, leaves either the old file or the new one, never a part: an
/// AtomicFile (common/atomic_file.h) whose data reaches the disk before the rename. InputError
/// naming the file on failure.
void WriteFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace mopad::io
