#include "io/text_file.h"

#include <fstream>
#include <iterator>

#include "common/atomic_file.h"
#include "common/error.h"

namespace mopad::io {

void WriteTextFile(const std::string& path, const std::string& text) {
  WriteWholeFile(path, text + "\n");
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot read the file");
  std::string s((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) throw InputError(path, "read failed");
  return s;
}

void WriteFileAtomically(const std::string& path, const std::string& bytes) {
  WriteWholeFile(path, bytes, /*sync=*/true);
}

}  // namespace mopad::io
