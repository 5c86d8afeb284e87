#include "io/text_file.h"

#include <fstream>

#include "common/error.h"

namespace mopad::io {

void WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot write the file");
  f << text << "\n";
  if (!f) throw InputError(path, "write failed");
}

}  // namespace mopad::io
