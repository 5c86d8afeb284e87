#include "io/step_writer.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "common/rng.h"

namespace mopad::io {
namespace {

bool IsKeyword(std::string_view s) {
  if (s.empty() || s[0] < 'A' || s[0] > 'Z') return false;
  for (char c : s)
    if (!((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

// Decodes one UTF-8 code point at s[i], advancing i; U+FFFD for a malformed sequence.
char32_t NextCodePoint(std::string_view s, std::size_t& i) {
  const auto b0 = static_cast<unsigned char>(s[i++]);
  if (b0 < 0x80) return b0;
  int extra = 0;
  char32_t cp = 0;
  if ((b0 & 0xE0) == 0xC0) {
    extra = 1, cp = b0 & 0x1F;
  } else if ((b0 & 0xF0) == 0xE0) {
    extra = 2, cp = b0 & 0x0F;
  } else if ((b0 & 0xF8) == 0xF0) {
    extra = 3, cp = b0 & 0x07;
  } else {
    return 0xFFFD;
  }
  for (int k = 0; k < extra; ++k) {
    if (i >= s.size() || (static_cast<unsigned char>(s[i]) & 0xC0) != 0x80) return 0xFFFD;
    cp = (cp << 6) | (static_cast<unsigned char>(s[i++]) & 0x3F);
  }
  const char32_t min_for_length[] = {0, 0x80, 0x800, 0x10000};
  if (cp < min_for_length[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
    return 0xFFFD;  // overlong, out of range or a surrogate
  return cp;
}

void AppendHex4(std::string& out, unsigned v) {
  static const char kHex[] = "0123456789ABCDEF";
  for (int shift = 12; shift >= 0; shift -= 4) out.push_back(kHex[(v >> shift) & 0xF]);
}

}  // namespace

int StepWriter::Add(std::string_view type, std::string_view args) {
  if (!IsKeyword(type))
    throw std::invalid_argument("StepWriter::Add: not an upper-case STEP keyword: " +
                                std::string(type));
  const int id = Count() + 1;
  std::string line = StepRef(id);
  line += '=';
  line += type;
  line += '(';
  line += args;
  line += ");";
  lines_.push_back(std::move(line));
  return id;
}

std::string StepWriter::Text(const StepHeader& h) const {
  std::string out = "ISO-10303-21;\nHEADER;\n";
  out += "FILE_DESCRIPTION((" + StepString(h.description) + "),'2;1');\n";
  out += "FILE_NAME(" + StepString(h.file_name) + "," + StepString(h.timestamp) + ",(" +
         StepString(h.author) + "),(" + StepString(h.organization) + ")," +
         StepString(h.preprocessor) + "," + StepString(h.originating_system) + ",'');\n";
  out += "FILE_SCHEMA((" + StepString(h.schema) + "));\nENDSEC;\nDATA;\n";
  for (const auto& line : lines_) {
    out += line;
    out += '\n';
  }
  out += "ENDSEC;\nEND-ISO-10303-21;\n";
  return out;
}

std::string StepString(std::string_view utf8) {
  std::string out = "'";
  std::size_t i = 0;
  bool in_x2 = false;  // inside a \X2\ ... \X0\ run
  while (i < utf8.size()) {
    const char32_t cp = NextCodePoint(utf8, i);
    const bool printable = cp >= 0x20 && cp <= 0x7E;
    if (printable && in_x2) {
      out += "\\X0\\";
      in_x2 = false;
    }
    if (printable) {
      if (cp == '\'')
        out += "''";
      else if (cp == '\\')
        out += "\\\\";
      else
        out.push_back(static_cast<char>(cp));
      continue;
    }
    if (!in_x2) {
      out += "\\X2\\";
      in_x2 = true;
    }
    if (cp >= 0x10000) {  // UTF-16 surrogate pair
      const char32_t v = cp - 0x10000;
      AppendHex4(out, 0xD800 + static_cast<unsigned>(v >> 10));
      AppendHex4(out, 0xDC00 + static_cast<unsigned>(v & 0x3FF));
    } else {
      AppendHex4(out, static_cast<unsigned>(cp));
    }
  }
  if (in_x2) out += "\\X0\\";
  out += '\'';
  return out;
}

std::string StepReal(double v) {
  if (!std::isfinite(v)) throw std::invalid_argument("StepReal: not a finite number");
  if (v == 0.0) return "0.";
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  const auto e = s.find('e');
  std::string mantissa = s.substr(0, e);
  std::string exponent = e == std::string::npos ? "" : s.substr(e + 1);
  if (mantissa.find('.') == std::string::npos) mantissa += '.';
  if (exponent.empty()) return mantissa;
  if (exponent[0] == '+') exponent.erase(0, 1);
  return mantissa + "E" + exponent;
}

// Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string&&.
std::string StepRef(int id) {
  std::string out = "#";
  out += std::to_string(id);
  return out;
}

std::string StepEnum(std::string_view name) {
  std::string out = ".";
  out += name;
  out += '.';
  return out;
}

std::string StepList(const std::vector<std::string>& items) {
  std::string out = "(";
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (k) out += ',';
    out += items[k];
  }
  return out + ")";
}

std::string StepRefList(const std::vector<int>& ids) {
  std::vector<std::string> refs;
  refs.reserve(ids.size());
  for (int id : ids) refs.push_back(StepRef(id));
  return StepList(refs);
}

std::string IfcGlobalId(std::string_view key) {
  static const char kAlphabet[] =
      "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_$";
  // Two 64-bit hashes with different start values, each byte mixed in (keys are short).
  std::uint64_t hi = Mix64(HashName(key) ^ 0x1F83D9ABFB41BD6Bull);
  std::uint64_t lo = 0x5BE0CD19137E2179ull;
  for (char c : key) lo = Mix64(lo ^ static_cast<unsigned char>(c));
  lo = Mix64(lo ^ key.size());
  // 128 bits = 2 + 21 * 6: the first character holds the top 2 bits.
  std::string out(22, '0');
  for (int k = 21; k >= 0; --k) {
    const unsigned digit = static_cast<unsigned>(lo & 0x3F);
    lo = (lo >> 6) | (hi << 58);
    hi >>= 6;
    out[static_cast<std::size_t>(k)] = kAlphabet[digit];
  }
  return out;
}

}  // namespace mopad::io
