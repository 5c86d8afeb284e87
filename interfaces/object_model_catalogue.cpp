#include "interfaces/object_model_catalogue.h"

#include <yaml-cpp/yaml.h>

#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/format.h"
#include "common/params.h"

// On-disk layout (version 1):
//   DIR/catalogue.yaml             format, version and one entry per model
//   DIR/<class>_colour.ppm         binary PPM (P6, maxval 255), top row first
//   DIR/<class>_depth.pfm          grey PFM (Pf), scale -1 = little-endian floats, rows stored
//                                  bottom row first as the PFM format specifies
// Doubles are written with 17 significant digits so that a round trip is exact.

namespace mopad::interfaces {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFormatName = "mopad-object-model-catalogue";
constexpr int kFormatVersion = 1;
constexpr int kMaxImageSide = 16384;

const char* MountingName(Mounting m) {
  switch (m) {
    case Mounting::kWall:
      return "wall";
    case Mounting::kCeiling:
      return "ceiling";
    case Mounting::kFloor:
      return "floor";
  }
  return "wall";
}

bool ParseMounting(const std::string& s, Mounting* out) {
  if (s == "wall")
    *out = Mounting::kWall;
  else if (s == "ceiling")
    *out = Mounting::kCeiling;
  else if (s == "floor")
    *out = Mounting::kFloor;
  else
    return false;
  return true;
}

// Class names become file names: keep them to [a-z0-9_-] so no path can escape DIR.
bool IsSafeName(const std::string& s) {
  if (s.empty() || s.size() > 128) return false;
  for (char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return s != "." && s != ".." && s.find("..") == std::string::npos;
}

void WriteFileBytes(const fs::path& path, const std::string& header, const char* data,
                    std::size_t size) {
  std::string bytes = header;
  bytes.append(data, size);
  WriteWholeFile(path.string(), bytes);
}

void CheckModelForWrite(const ObjectModel& m, const std::string& dir) {
  const std::string where = dir + ": model '" + m.class_name + "'";
  if (!IsSafeName(m.class_name))
    throw InputError(dir, "object model class name not usable as a file name",
                     "'" + m.class_name + "'", "[A-Za-z0-9_.-]+");
  if (!m.marks.empty() && !IsSafeName(m.marks))
    throw InputError(where, "bad class name in 'marks'", "'" + m.marks + "'", "[A-Za-z0-9_.-]+");
  for (auto [name, v] :
       {std::pair{"width", m.width}, {"height", m.height}, {"pixel_size", m.pixel_size}}) {
    if (!std::isfinite(v) || v <= 0.0)
      throw InputError(where, std::string(name) + " must be positive", FormatNumbers("%.17g", v),
                       "> 0");
  }
  if (!std::isfinite(m.depth) || m.depth < 0.0)
    throw InputError(where, "depth must be non-negative", FormatNumbers("%.17g", m.depth), ">= 0");
  if (m.image_width <= 0 || m.image_height <= 0 || m.image_width > kMaxImageSide ||
      m.image_height > kMaxImageSide)
    throw InputError(where, "image size out of range",
                     std::to_string(m.image_width) + "x" + std::to_string(m.image_height),
                     "1.." + std::to_string(kMaxImageSide) + " per side");
  const std::size_t n = static_cast<std::size_t>(m.image_width) * m.image_height;
  if (m.colour_rgb.size() != 3 * n)
    throw InputError(where, "colour image size mismatch", std::to_string(m.colour_rgb.size()),
                     std::to_string(3 * n) + " bytes");
  if (m.depth_m.size() != n)
    throw InputError(where, "depth image size mismatch", std::to_string(m.depth_m.size()),
                     std::to_string(n) + " values");
}

// ---- reading helpers ----

std::vector<char> ReadFileBytes(const fs::path& path, const std::string& where_ref) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(where_ref, "missing image file", "'" + path.string() + "'",
                     "an existing file");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path.string(), "cannot open file");
  return std::vector<char>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

// Netpbm-style header tokens: whitespace-separated, '#' comments to end of line (PPM only).
class HeaderReader {
 public:
  HeaderReader(const std::vector<char>& b, std::string path, bool comments)
      : b_(b), path_(std::move(path)), comments_(comments) {}
  std::string Token(const std::string& what) {
    SkipSpace();
    std::string t;
    while (pos_ < b_.size() && !std::isspace(static_cast<unsigned char>(b_[pos_])) && t.size() < 64)
      t += b_[pos_++];
    if (t.empty()) throw InputError(path_, "truncated header", "end of file", what);
    return t;
  }
  long Integer(const std::string& what) {
    const std::string t = Token(what);
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(t.c_str(), &end, 10);
    if (*end != '\0' || errno != 0 || t.empty())
      throw InputError(path_, "bad header field", "'" + t + "'", what);
    return v;
  }
  double Real(const std::string& what) {
    const std::string t = Token(what);
    std::istringstream is(t);
    is.imbue(std::locale::classic());
    double v = 0.0;
    if (!(is >> v) || !is.eof()) throw InputError(path_, "bad header field", "'" + t + "'", what);
    return v;
  }
  /// Exactly one whitespace byte ends the header; returns the data offset.
  std::size_t EndOfHeader() {
    if (pos_ >= b_.size() || !std::isspace(static_cast<unsigned char>(b_[pos_])))
      throw InputError(path_, "truncated header", "end of file", "one whitespace byte");
    return pos_ + 1;
  }

 private:
  void SkipSpace() {
    while (pos_ < b_.size()) {
      const char c = b_[pos_];
      if (std::isspace(static_cast<unsigned char>(c))) {
        ++pos_;
      } else if (comments_ && c == '#') {
        while (pos_ < b_.size() && b_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }
  const std::vector<char>& b_;
  std::string path_;
  bool comments_;
  std::size_t pos_ = 0;
};

void CheckSize(const std::string& path, long w, long h, int ew, int eh) {
  if (w != ew || h != eh)
    throw InputError(path, "image size does not match catalogue.yaml",
                     std::to_string(w) + "x" + std::to_string(h),
                     std::to_string(ew) + "x" + std::to_string(eh));
}

void CheckDataSize(const std::string& path, std::size_t have, std::size_t want) {
  if (have != want)
    throw InputError(path, "image data size mismatch", std::to_string(have) + " bytes",
                     std::to_string(want) + " bytes");
}

std::vector<std::uint8_t> ReadPpm(const fs::path& path, int w, int h, const std::string& ref) {
  const std::vector<char> b = ReadFileBytes(path, ref);
  const std::string p = path.string();
  HeaderReader hr(b, p, true);
  const std::string magic = hr.Token("magic 'P6'");
  if (magic != "P6") throw InputError(p, "bad PPM magic", "'" + magic + "'", "'P6'");
  const long fw = hr.Integer("image width");
  const long fh = hr.Integer("image height");
  const long maxval = hr.Integer("maxval 255");
  if (maxval != 255) throw InputError(p, "unsupported PPM maxval", std::to_string(maxval), "255");
  CheckSize(p, fw, fh, w, h);
  const std::size_t off = hr.EndOfHeader();
  const std::size_t want = static_cast<std::size_t>(w) * h * 3;
  CheckDataSize(p, b.size() - off, want);
  return std::vector<std::uint8_t>(b.begin() + static_cast<std::ptrdiff_t>(off), b.end());
}

std::vector<float> ReadPfm(const fs::path& path, int w, int h, const std::string& ref) {
  const std::vector<char> b = ReadFileBytes(path, ref);
  const std::string p = path.string();
  HeaderReader hr(b, p, false);
  const std::string magic = hr.Token("magic 'Pf'");
  if (magic != "Pf") throw InputError(p, "bad PFM magic", "'" + magic + "'", "'Pf' (greyscale)");
  const long fw = hr.Integer("image width");
  const long fh = hr.Integer("image height");
  const double scale = hr.Real("scale (negative: little-endian)");
  if (!std::isfinite(scale) || scale == 0.0)
    throw InputError(p, "bad PFM scale", FormatNumbers("%.17g", scale), "a non-zero number");
  CheckSize(p, fw, fh, w, h);
  const std::size_t off = hr.EndOfHeader();
  const std::size_t n = static_cast<std::size_t>(w) * h;
  CheckDataSize(p, b.size() - off, 4 * n);
  const bool little = scale < 0.0;
  std::vector<float> out(n);
  for (int row = 0; row < h; ++row) {
    // PFM stores the bottom row first.
    const std::size_t src_row = static_cast<std::size_t>(h - 1 - row);
    for (int col = 0; col < w; ++col) {
      const char* q = &b[off + 4 * (src_row * w + col)];
      std::uint32_t u = 0;
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t byte = static_cast<unsigned char>(q[little ? k : 3 - k]);
        u |= byte << (8 * k);
      }
      const float v = std::bit_cast<float>(u);
      if (!std::isfinite(v))
        throw InputError(p, "non-finite depth value at pixel (" + std::to_string(col) + ", " +
                                std::to_string(row) + ")");
      out[static_cast<std::size_t>(row) * w + col] = v;
    }
  }
  return out;
}

template <class T>
T Get(const YAML::Node& map, const char* key, const std::string& file, const std::string& what) {
  const YAML::Node n = map[key];
  if (!n) throw InputError(YamlWhere(file, map), "missing key '" + std::string(key) + "'");
  if (!n.IsScalar())
    throw InputError(YamlWhere(file, n), "wrong type for '" + std::string(key) + "'",
                     "a " + std::string(n.IsMap()        ? "map"
                                        : n.IsSequence() ? "sequence"
                                                         : "null"),
                     what);
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(YamlWhere(file, n), "wrong type for '" + std::string(key) + "'",
                     "'" + n.Scalar() + "'", what);
  }
}

double GetPositive(const YAML::Node& map, const char* key, const std::string& file,
                   bool allow_zero) {
  const double v = Get<double>(map, key, file, "a number");
  if (!std::isfinite(v) || v < 0.0 || (!allow_zero && v == 0.0))
    throw InputError(YamlWhere(file, map[key]), "'" + std::string(key) + "' out of range",
                     FormatNumbers("%.17g", v), allow_zero ? ">= 0" : "> 0");
  return v;
}

}  // namespace

const ObjectModel* ObjectModelCatalogue::Find(const std::string& class_name) const {
  for (const auto& m : models)
    if (m.class_name == class_name) return &m;
  return nullptr;
}

void WriteCatalogue(const ObjectModelCatalogue& catalogue, const std::string& dir) {
  std::set<std::string> seen;
  for (const auto& m : catalogue.models) {
    CheckModelForWrite(m, dir);
    if (!seen.insert(m.class_name).second)
      throw InputError(dir, "duplicate object model class", "'" + m.class_name + "'",
                       "unique class names");
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) throw InputError(dir, "cannot create directory");

  std::ostringstream y;
  y.imbue(std::locale::classic());
  y << "# Object-model catalogue (robot-side BSC database): sizes in metres, colour as binary\n"
    << "# PPM (P6), depth (protrusion from the host surface, m) as little-endian PFM (Pf).\n"
    << "format: " << kFormatName << "\n"
    << "version: " << kFormatVersion << "\n";
  if (catalogue.models.empty())
    y << "models: []\n";
  else
    y << "models:\n";
  for (const auto& m : catalogue.models) {
    const std::string colour_file = m.class_name + "_colour.ppm";
    const std::string depth_file = m.class_name + "_depth.pfm";
    y << "  - class_name: " << m.class_name << "\n"
      << "    mounting: " << MountingName(m.mounting) << "\n"
      << "    width: " << FormatNumbers("%.17g", m.width) << "\n"
      << "    height: " << FormatNumbers("%.17g", m.height) << "\n"
      << "    depth: " << FormatNumbers("%.17g", m.depth) << "\n";
    if (!m.marks.empty()) y << "    marks: " << m.marks << "\n";
    y << "    pixel_size: " << FormatNumbers("%.17g", m.pixel_size) << "\n"
      << "    image_width: " << m.image_width << "\n"
      << "    image_height: " << m.image_height << "\n"
      << "    colour_file: " << colour_file << "\n"
      << "    depth_file: " << depth_file << "\n";

    const std::string ppm_header =
        "P6\n" + std::to_string(m.image_width) + " " + std::to_string(m.image_height) + "\n255\n";
    WriteFileBytes(fs::path(dir) / colour_file, ppm_header,
                   reinterpret_cast<const char*>(m.colour_rgb.data()), m.colour_rgb.size());

    const std::string pfm_header =
        "Pf\n" + std::to_string(m.image_width) + " " + std::to_string(m.image_height) + "\n-1\n";
    std::string data;
    data.reserve(m.depth_m.size() * 4);
    for (int row = m.image_height - 1; row >= 0; --row) {  // PFM: bottom row first
      for (int col = 0; col < m.image_width; ++col) {
        const std::uint32_t u = std::bit_cast<std::uint32_t>(
            m.depth_m[static_cast<std::size_t>(row) * m.image_width + col]);
        for (int k = 0; k < 4; ++k) data += static_cast<char>((u >> (8 * k)) & 0xFF);
      }
    }
    WriteFileBytes(fs::path(dir) / depth_file, pfm_header, data.data(), data.size());
  }
  const fs::path yaml_path = fs::path(dir) / "catalogue.yaml";
  const std::string text = y.str();
  WriteFileBytes(yaml_path, "", text.data(), text.size());
}

ObjectModelCatalogue ReadCatalogue(const std::string& dir) {
  const std::string file = (fs::path(dir) / "catalogue.yaml").string();
  const YAML::Node root = LoadYamlFile(file);
  if (!root.IsMap()) throw InputError(YamlWhere(file, root), "catalogue must be a YAML map");
  RejectUnknownKeys(root, {"format", "version", "models"}, file, "");
  const std::string format = Get<std::string>(root, "format", file, "a string");
  if (format != kFormatName)
    throw InputError(YamlWhere(file, root["format"]), "unknown catalogue format",
                     "'" + format + "'", std::string("'") + kFormatName + "'");
  const int version = Get<int>(root, "version", file, "an integer");
  if (version != kFormatVersion)
    throw InputError(YamlWhere(file, root["version"]), "unsupported catalogue version",
                     std::to_string(version), std::to_string(kFormatVersion));
  const YAML::Node models = root["models"];
  if (!models) throw InputError(YamlWhere(file, root), "missing key 'models'");
  if (!models.IsSequence())
    throw InputError(YamlWhere(file, models), "'models' must be a sequence");

  ObjectModelCatalogue cat;
  std::set<std::string> seen;
  for (const YAML::Node& n : models) {
    if (!n.IsMap()) throw InputError(YamlWhere(file, n), "each model must be a map");
    RejectUnknownKeys(n,
                      {"class_name", "mounting", "width", "height", "depth", "marks", "pixel_size",
                       "image_width", "image_height", "colour_file", "depth_file"},
                      file, "models[].");
    ObjectModel m;
    m.class_name = Get<std::string>(n, "class_name", file, "a string");
    if (!IsSafeName(m.class_name))
      throw InputError(YamlWhere(file, n["class_name"]), "bad class name", "'" + m.class_name + "'",
                       "[A-Za-z0-9_.-]+");
    if (!seen.insert(m.class_name).second)
      throw InputError(YamlWhere(file, n["class_name"]), "duplicate class name",
                       "'" + m.class_name + "'", "unique class names");
    const std::string mounting = Get<std::string>(n, "mounting", file, "wall|ceiling|floor");
    if (!ParseMounting(mounting, &m.mounting))
      throw InputError(YamlWhere(file, n["mounting"]), "unknown mounting", "'" + mounting + "'",
                       "wall, ceiling or floor");
    m.width = GetPositive(n, "width", file, false);
    m.height = GetPositive(n, "height", file, false);
    m.depth = GetPositive(n, "depth", file, true);
    if (n["marks"]) {
      m.marks = Get<std::string>(n, "marks", file, "a class name");
      if (!IsSafeName(m.marks))
        throw InputError(YamlWhere(file, n["marks"]), "bad class name in 'marks'",
                         "'" + m.marks + "'", "[A-Za-z0-9_.-]+");
    }
    m.pixel_size = GetPositive(n, "pixel_size", file, false);
    for (auto [key, out] :
         {std::pair{"image_width", &m.image_width}, std::pair{"image_height", &m.image_height}}) {
      *out = Get<int>(n, key, file, "an integer");
      if (*out <= 0 || *out > kMaxImageSide)
        throw InputError(YamlWhere(file, n[key]), "'" + std::string(key) + "' out of range",
                         std::to_string(*out), "[1, " + std::to_string(kMaxImageSide) + "]");
    }
    const std::string colour_file = Get<std::string>(n, "colour_file", file, "a file name");
    const std::string depth_file = Get<std::string>(n, "depth_file", file, "a file name");
    for (auto [key, name] :
         {std::pair{"colour_file", &colour_file}, std::pair{"depth_file", &depth_file}}) {
      if (!IsSafeName(*name))
        throw InputError(YamlWhere(file, n[key]),
                         "file name must be a plain name inside the "
                         "catalogue directory",
                         "'" + *name + "'", "[A-Za-z0-9_.-]+");
    }
    m.colour_rgb = ReadPpm(fs::path(dir) / colour_file, m.image_width, m.image_height,
                           YamlWhere(file, n["colour_file"]));
    m.depth_m = ReadPfm(fs::path(dir) / depth_file, m.image_width, m.image_height,
                        YamlWhere(file, n["depth_file"]));
    cat.models.push_back(std::move(m));
  }
  return cat;
}

}  // namespace mopad::interfaces
