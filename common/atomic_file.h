#pragma once
// Files that appear whole or not at all: every file a run writes goes through AtomicFile, so a
// process killed at any moment (or a write that fails half way) never leaves a part of a file
// that a later reader (`mopad eval`, `--resume`, a suite) would trust.

#include <string>

namespace mopad {

/// One file written under a temporary name beside its final path (same folder, so the rename
/// stays on one file system and is atomic), then renamed over it by Commit():
///
///   AtomicFile file(path);
///   std::ofstream out(file.TempPath(), std::ios::binary);   // or fopen, a library writer...
///   out << text;
///   out.close();
///   file.Commit();   // now `path` holds the new bytes; before, it held the old file or none
///
/// Destroyed without Commit() (an exception, an early return) it removes the temporary file. A
/// killed process can leave the temporary file (TempPath(), `path` + ".tmp") beside the old one;
/// the next write of `path` replaces it.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&& other) noexcept;

  /// The final path.
  const std::string& Path() const { return path_; }
  /// Where to write the bytes (`Path()` + ".tmp").
  const std::string& TempPath() const { return tmp_; }
  /// Renames the written temporary file over Path(). With `sync`, its data reaches the disk
  /// first (then a power cut, not only a killed process, leaves the old or the new file).
  /// InputError naming the file when the temporary file is missing or cannot be renamed.
  void Commit(bool sync = false);

 private:
  void Discard() noexcept;
  std::string path_, tmp_;
  bool open_ = false;  ///< a temporary file may exist that Commit() has not renamed
};

/// Writes `bytes` (as given) to `path` through an AtomicFile. InputError naming the file when
/// it cannot be written.
void WriteWholeFile(const std::string& path, const std::string& bytes, bool sync = false);

}  // namespace mopad
