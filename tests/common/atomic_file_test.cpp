// common/atomic_file.h: a file appears whole or not at all, and no temporary file remains.
#include "common/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>

#include "common/error.h"
#include "tests/process_temp_dir.h"

namespace mopad {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The names in `dir`, sorted.
std::string Listing(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  std::string s;
  for (const auto& n : names) s += n + " ";
  return s;
}

TEST(AtomicFile, CommitReplacesTheFileWholeAndLeavesNoTemporaryFile) {
  const fs::path dir = test_support::ProcessTempDir("mopad_atomic_", "_commit");
  const std::string path = (dir / "a.json").string();
  WriteWholeFile(path, "old\n");
  {
    AtomicFile file(path);
    std::ofstream(file.TempPath(), std::ios::binary) << "new, longer\n";
    EXPECT_EQ(Read(path), "old\n") << "the final file changed before Commit()";
    file.Commit();
  }
  EXPECT_EQ(Read(path), "new, longer\n");
  EXPECT_EQ(Listing(dir), "a.json ");
  WriteWholeFile(path, std::string("\0bytes\n", 7), /*sync=*/true);
  EXPECT_EQ(Read(path), std::string("\0bytes\n", 7));
  EXPECT_EQ(Listing(dir), "a.json ");
}

// A writer that throws half way leaves the old file (or none) and no temporary file.
TEST(AtomicFile, AWriteThatThrowsLeavesTheOldFileOrNoneAndNoTemporaryFile) {
  const fs::path dir = test_support::ProcessTempDir("mopad_atomic_", "_throw");
  const std::string kept = (dir / "kept.json").string(), fresh = (dir / "fresh.json").string();
  WriteWholeFile(kept, "{\"whole\": true}\n");
  for (const std::string& path : {kept, fresh}) {
    try {
      AtomicFile file(path);
      std::ofstream out(file.TempPath(), std::ios::binary);
      out << "{\"half";
      out.flush();
      throw std::runtime_error("disk full");
    } catch (const std::runtime_error&) {
    }
  }
  EXPECT_EQ(Read(kept), "{\"whole\": true}\n");
  EXPECT_FALSE(fs::exists(fresh));
  EXPECT_EQ(Listing(dir), "kept.json ");
}

TEST(AtomicFile, AFolderThatDoesNotExistIsAnInputErrorNamingTheFile) {
  const fs::path dir = test_support::ProcessTempDir("mopad_atomic_", "_missing");
  const std::string path = (dir / "no" / "such" / "f.txt").string();
  try {
    WriteWholeFile(path, "x");
    FAIL() << "written into a folder that does not exist";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": error: cannot write the file", 0), 0u)
        << e.what();
  }
  // Nothing written to TempPath(): Commit() refuses, naming the file.
  AtomicFile file((dir / "never.txt").string());
  EXPECT_THROW(file.Commit(), InputError);
  EXPECT_EQ(Listing(dir), "");
}

}  // namespace
}  // namespace mopad
