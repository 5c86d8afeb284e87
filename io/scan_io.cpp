#include "io/scan_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>

#include "common/error.h"
#include "common/format.h"

namespace mopad::io {

static_assert(std::endian::native == std::endian::little,
              "PLY writer assumes a little-endian host");

namespace {

constexpr int kCountWidth = 20;  // digits reserved for the vertex count (fits any uint64)

const char* PlyTypeName(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
      return "char";
    case PlyType::kUInt8:
      return "uchar";
    case PlyType::kInt16:
      return "short";
    case PlyType::kUInt16:
      return "ushort";
    case PlyType::kInt32:
      return "int";
    case PlyType::kUInt32:
      return "uint";
    case PlyType::kFloat32:
      return "float";
    case PlyType::kFloat64:
      return "double";
  }
  return "?";
}

int PlyTypeSize(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUInt8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUInt16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUInt32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

bool ParsePlyType(const std::string& s, PlyType* t) {
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUInt8},
      {"uint8", PlyType::kUInt8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUInt16},  {"uint16", PlyType::kUInt16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUInt32},     {"uint32", PlyType::kUInt32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [name, type] : kNames) {
    if (s == name) {
      *t = type;
      return true;
    }
  }
  return false;
}

void PutValue(char* dst, PlyType t, double v) {
  switch (t) {
    case PlyType::kInt8: {
      auto x = static_cast<std::int8_t>(v);
      std::memcpy(dst, &x, 1);
      break;
    }
    case PlyType::kUInt8: {
      auto x = static_cast<std::uint8_t>(v);
      std::memcpy(dst, &x, 1);
      break;
    }
    case PlyType::kInt16: {
      auto x = static_cast<std::int16_t>(v);
      std::memcpy(dst, &x, 2);
      break;
    }
    case PlyType::kUInt16: {
      auto x = static_cast<std::uint16_t>(v);
      std::memcpy(dst, &x, 2);
      break;
    }
    case PlyType::kInt32: {
      auto x = static_cast<std::int32_t>(v);
      std::memcpy(dst, &x, 4);
      break;
    }
    case PlyType::kUInt32: {
      auto x = static_cast<std::uint32_t>(v);
      std::memcpy(dst, &x, 4);
      break;
    }
    case PlyType::kFloat32: {
      auto x = static_cast<float>(v);
      std::memcpy(dst, &x, 4);
      break;
    }
    case PlyType::kFloat64:
      std::memcpy(dst, &v, 8);
      break;
  }
}

double GetValue(const char* src, PlyType t) {
  switch (t) {
    case PlyType::kInt8: {
      std::int8_t x;
      std::memcpy(&x, src, 1);
      return x;
    }
    case PlyType::kUInt8: {
      std::uint8_t x;
      std::memcpy(&x, src, 1);
      return x;
    }
    case PlyType::kInt16: {
      std::int16_t x;
      std::memcpy(&x, src, 2);
      return x;
    }
    case PlyType::kUInt16: {
      std::uint16_t x;
      std::memcpy(&x, src, 2);
      return x;
    }
    case PlyType::kInt32: {
      std::int32_t x;
      std::memcpy(&x, src, 4);
      return x;
    }
    case PlyType::kUInt32: {
      std::uint32_t x;
      std::memcpy(&x, src, 4);
      return x;
    }
    case PlyType::kFloat32: {
      float x;
      std::memcpy(&x, src, 4);
      return x;
    }
    case PlyType::kFloat64: {
      double x;
      std::memcpy(&x, src, 8);
      return x;
    }
  }
  return 0;
}

std::string PadCount(std::uint64_t n) {
  std::string s = std::to_string(n);
  s.resize(kCountWidth, ' ');
  return s;
}

// Opens `file`'s temporary file; errors name its final path.
std::FILE* OpenForWrite(const AtomicFile& file) {
  std::FILE* f = std::fopen(file.TempPath().c_str(), "wb");
  if (!f) throw InputError(file.Path(), "cannot open file for writing", std::strerror(errno));
  return f;
}

void WriteOrThrow(std::FILE* f, const void* data, std::size_t n, const std::string& path) {
  if (n && std::fwrite(data, 1, n, f) != n)
    throw InputError(path, "write failed", std::strerror(errno));
}

// TLS-scan PLY header comments and properties.
std::vector<std::string> TlsComments(const TlsScan& s) {
  return {"mopad_tls_scan 1",
          "mopad_scan_id " + std::to_string(s.scan_id),
          "mopad_start_time " + FormatShortest(s.start_time),
          "mopad_grid " + std::to_string(s.rows) + " " + std::to_string(s.columns) + " " +
              FormatShortest(s.azimuth_min) + " " + FormatShortest(s.azimuth_step) + " " +
              FormatShortest(s.elevation_max) + " " + FormatShortest(s.elevation_step),
          "mopad_X_BS" + PoseWords(s.X_BS),
          "mopad_X_MS_estimate" + PoseWords(s.X_MS_estimate)};
}

std::vector<std::pair<std::string, PlyType>> TlsProperties(bool wide_row, bool wide_col) {
  return {{"x", PlyType::kFloat32},
          {"y", PlyType::kFloat32},
          {"z", PlyType::kFloat32},
          {"red", PlyType::kUInt8},
          {"green", PlyType::kUInt8},
          {"blue", PlyType::kUInt8},
          {"scalar_intensity", PlyType::kFloat32},
          {"scalar_range", PlyType::kFloat32},
          {"scalar_row", wide_row ? PlyType::kUInt32 : PlyType::kUInt16},
          {"scalar_column", wide_col ? PlyType::kUInt32 : PlyType::kUInt16},
          {"scalar_timestamp", PlyType::kFloat64}};
}

struct PlyHeader {
  std::vector<std::string> comments;
  std::uint64_t vertex_count = 0;
  struct Prop {
    std::string name;
    PlyType type;
    int offset;
  };
  std::vector<Prop> props;
  int stride = 0;
  std::size_t data_offset = 0;
};

PlyHeader ParseHeader(std::istream& in, const std::string& path) {
  PlyHeader h;
  std::string line;
  int line_no = 0;
  auto where = [&] { return path + ":" + std::to_string(line_no); };
  if (!std::getline(in, line) || (++line_no, line != "ply")) {
    throw InputError(path + ":1", "not a PLY file", "'" + line.substr(0, 20) + "'", "'ply'");
  }
  bool in_vertex = false, seen_vertex = false, format_ok = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "end_header") {
      if (!format_ok) throw InputError(where(), "missing 'format' line");
      if (!seen_vertex) throw InputError(where(), "no vertex element");
      h.data_offset = static_cast<std::size_t>(in.tellg());
      return h;
    } else if (word == "format") {
      std::string fmt, ver;
      ls >> fmt >> ver;
      if (fmt != "binary_little_endian") {
        throw InputError(where(), "unsupported PLY format", fmt, "binary_little_endian");
      }
      format_ok = true;
    } else if (word == "comment" || word == "obj_info") {
      const auto pos = line.find(word) + word.size();
      h.comments.push_back(pos < line.size() ? line.substr(pos + 1) : "");
    } else if (word == "element") {
      std::string name;
      std::uint64_t n = 0;
      ls >> name >> n;
      if (ls.fail()) throw InputError(where(), "malformed element line", "'" + line + "'");
      if (name == "vertex") {
        if (seen_vertex) throw InputError(where(), "two vertex elements");
        in_vertex = seen_vertex = true;
        h.vertex_count = n;
      } else {
        if (!seen_vertex)
          throw InputError(where(), "element before 'vertex' is not supported", name);
        in_vertex = false;
      }
    } else if (word == "property") {
      if (!in_vertex) continue;  // properties of later elements are ignored
      std::string type, name;
      ls >> type >> name;
      PlyType t;
      if (type == "list") throw InputError(where(), "list property in vertex element", name);
      if (!ParsePlyType(type, &t)) throw InputError(where(), "unknown property type", type);
      h.props.push_back({name, t, h.stride});
      h.stride += PlyTypeSize(t);
    } else if (!word.empty()) {
      throw InputError(where(), "unknown header keyword", word);
    }
  }
  throw InputError(path, "missing end_header");
}

bool ParsePoseWords(std::istringstream& ls, Eigen::Isometry3d* X) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) ls >> m(r, c);
  if (ls.fail()) return false;
  X->matrix() = m;
  return true;
}

}  // namespace

std::string PoseWords(const Eigen::Isometry3d& X) {
  std::string s;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      s += ' ';
      s += FormatShortest(X.matrix()(r, c));
    }
  return s;
}

const ScalarField* PointCloud::Field(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

void WritePly(const std::string& path, const PointCloud& cloud) {
  const std::size_t n = cloud.points.size();
  if (!cloud.colors.empty() && cloud.colors.size() != n) {
    throw InputError(path, "colour count differs from point count",
                     std::to_string(cloud.colors.size()), std::to_string(n));
  }
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  for (const auto& c : cloud.comments) {
    if (c.find('\n') != std::string::npos) throw InputError(path, "PLY comment contains a newline");
    header += "comment " + c + "\n";
  }
  header += "element vertex " + std::to_string(n) + "\n";
  header += "property float x\nproperty float y\nproperty float z\n";
  int stride = 12;
  if (!cloud.colors.empty()) {
    header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    stride += 3;
  }
  for (const auto& f : cloud.fields) {
    if (f.values.size() != n) {
      throw InputError(path, "field '" + f.name + "' has the wrong length",
                       std::to_string(f.values.size()), std::to_string(n));
    }
    if (f.name.empty() || f.name.find_first_of(" \t\n") != std::string::npos) {
      throw InputError(path, "invalid PLY property name", "'" + f.name + "'");
    }
    header += std::string("property ") + PlyTypeName(f.type) + " " + f.name + "\n";
    stride += PlyTypeSize(f.type);
  }
  header += "end_header\n";
  AtomicFile out(path);
  std::FILE* file = OpenForWrite(out);
  try {
    WriteOrThrow(file, header.data(), header.size(), path);
    constexpr std::size_t kChunk = 1 << 16;
    std::vector<char> buf(kChunk * stride);
    for (std::size_t i0 = 0; i0 < n; i0 += kChunk) {
      const std::size_t i1 = std::min(n, i0 + kChunk);
      char* p = buf.data();
      for (std::size_t i = i0; i < i1; ++i) {
        std::memcpy(p, cloud.points[i].data(), 12);
        p += 12;
        if (!cloud.colors.empty()) {
          std::memcpy(p, cloud.colors[i].data(), 3);
          p += 3;
        }
        for (const auto& f : cloud.fields) {
          PutValue(p, f.type, f.values[i]);
          p += PlyTypeSize(f.type);
        }
      }
      WriteOrThrow(file, buf.data(), static_cast<std::size_t>(p - buf.data()), path);
    }
  } catch (...) {
    std::fclose(file);
    throw;
  }
  if (std::fclose(file) != 0) throw InputError(path, "write failed", std::strerror(errno));
  out.Commit();
}

PointCloud ReadPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file");
  const PlyHeader h = ParseHeader(in, path);
  const PlyHeader::Prop *px = nullptr, *py = nullptr, *pz = nullptr, *pr = nullptr, *pg = nullptr,
                        *pb = nullptr;
  PointCloud cloud;
  cloud.comments = h.comments;
  std::vector<const PlyHeader::Prop*> others;
  for (const auto& p : h.props) {
    if (p.name == "x")
      px = &p;
    else if (p.name == "y")
      py = &p;
    else if (p.name == "z")
      pz = &p;
    else if (p.name == "red")
      pr = &p;
    else if (p.name == "green")
      pg = &p;
    else if (p.name == "blue")
      pb = &p;
    else
      others.push_back(&p);
  }
  if (!px || !py || !pz) throw InputError(path, "vertex element lacks x, y or z");
  const bool has_color = pr && pg && pb;
  const std::uint64_t n = h.vertex_count;
  in.seekg(0, std::ios::end);
  const std::uint64_t size = static_cast<std::uint64_t>(in.tellg());
  // Compared as a count (n * stride can wrap around for a hostile vertex count).
  if (size < h.data_offset || n > (size - h.data_offset) / static_cast<std::uint64_t>(h.stride)) {
    throw InputError(path, "file truncated", std::to_string(size) + " bytes",
                     std::to_string(n) + " vertices of " + std::to_string(h.stride) +
                         " bytes after a header of " + std::to_string(h.data_offset));
  }
  in.seekg(static_cast<std::streamoff>(h.data_offset));
  cloud.points.resize(n);
  if (has_color) cloud.colors.resize(n);
  for (const auto* p : others) cloud.fields.push_back({p->name, p->type, std::vector<double>(n)});
  constexpr std::uint64_t kChunk = 1 << 16;
  std::vector<char> buf(kChunk * h.stride);
  for (std::uint64_t i0 = 0; i0 < n; i0 += kChunk) {
    const std::uint64_t m = std::min(kChunk, n - i0);
    in.read(buf.data(), static_cast<std::streamsize>(m * h.stride));
    if (!in) throw InputError(path, "read failed");
    for (std::uint64_t k = 0; k < m; ++k) {
      const char* rec = buf.data() + k * h.stride;
      const std::uint64_t i = i0 + k;
      cloud.points[i] = Eigen::Vector3f(static_cast<float>(GetValue(rec + px->offset, px->type)),
                                        static_cast<float>(GetValue(rec + py->offset, py->type)),
                                        static_cast<float>(GetValue(rec + pz->offset, pz->type)));
      if (has_color) {
        cloud.colors[i] = {static_cast<std::uint8_t>(GetValue(rec + pr->offset, pr->type)),
                           static_cast<std::uint8_t>(GetValue(rec + pg->offset, pg->type)),
                           static_cast<std::uint8_t>(GetValue(rec + pb->offset, pb->type))};
      }
      for (std::size_t f = 0; f < others.size(); ++f) {
        cloud.fields[f].values[i] = GetValue(rec + others[f]->offset, others[f]->type);
      }
    }
  }
  return cloud;
}

// ---------------------------------------------------------------- TLS PLY

PlyStreamWriter::PlyStreamWriter(const std::string& path, const std::vector<std::string>& comments,
                                 const std::vector<std::pair<std::string, PlyType>>& properties,
                                 std::uint64_t expected_points)
    : path_(path), out_(path) {
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  for (const auto& c : comments) {
    if (c.find('\n') != std::string::npos) throw InputError(path, "PLY comment contains a newline");
    header += "comment " + c + "\n";
  }
  header += "element vertex ";
  count_offset_ = static_cast<long>(header.size());
  header += PadCount(0) + "\n";
  for (const auto& [name, type] : properties) {
    header += std::string("property ") + PlyTypeName(type) + " " + name + "\n";
    record_size_ += PlyTypeSize(type);
  }
  header += "end_header\n";
  file_ = OpenForWrite(out_);
  WriteOrThrow(file_, header.data(), header.size(), path_);
  bytes_ = header.size();
  if (expected_points > 0) {
    // Preallocating lets the kernel skip block allocation during the writes (about 3x faster
    // buffered writes on ext4); Close() trims the file to its real length.
    std::fflush(file_);
    (void)posix_fallocate(fileno(file_), 0,
                          static_cast<off_t>(bytes_ + expected_points * record_size_));
  }
}

PlyStreamWriter::~PlyStreamWriter() {
  if (file_) std::fclose(file_);
}

void PlyStreamWriter::Append(const std::string& bytes, std::uint64_t count) {
  WriteOrThrow(file_, bytes.data(), bytes.size(), path_);
  bytes_ += bytes.size();
  count_ += count;
}

void PlyStreamWriter::Close() {
  if (!file_) return;
  std::FILE* f = file_;
  file_ = nullptr;
  bool ok = std::fflush(f) == 0;
  ok = ok && ftruncate(fileno(f), static_cast<off_t>(bytes_)) == 0;
  ok = ok && std::fseek(f, count_offset_, SEEK_SET) == 0;
  const std::string count = PadCount(count_);
  ok = ok && std::fwrite(count.data(), 1, count.size(), f) == count.size();
  ok = (std::fclose(f) == 0) && ok;
  if (!ok) throw InputError(path_, "write failed", std::strerror(errno));
  out_.Commit();
}

TlsPlyStreamWriter::TlsPlyStreamWriter(const std::string& path, const TlsScan& meta,
                                       std::uint64_t expected_points)
    : wide_row_(meta.rows > 65535),
      wide_col_(meta.columns > 65535),
      ply_(path, TlsComments(meta), TlsProperties(wide_row_, wide_col_), expected_points) {}

std::uint64_t TlsPlyStreamWriter::EncodePoints(std::span<const TlsPoint> points, bool wide_row,
                                               bool wide_col, std::string& out) {
  const std::size_t record = 35 + (wide_row ? 2 : 0) + (wide_col ? 2 : 0);
  const std::size_t start = out.size();
  out.resize(start + points.size() * record);
  char* p = out.data() + start;
  std::uint64_t n = 0;
  for (const TlsPoint& q : points) {
    if (!q.valid()) continue;
    std::memcpy(p, &q.x, 4);
    std::memcpy(p + 4, &q.y, 4);
    std::memcpy(p + 8, &q.z, 4);
    p[12] = static_cast<char>(q.r);
    p[13] = static_cast<char>(q.g);
    p[14] = static_cast<char>(q.b);
    std::memcpy(p + 15, &q.intensity, 4);
    std::memcpy(p + 19, &q.range, 4);
    p += 23;
    if (wide_row) {
      std::memcpy(p, &q.row, 4);
      p += 4;
    } else {
      const auto r = static_cast<std::uint16_t>(q.row);
      std::memcpy(p, &r, 2);
      p += 2;
    }
    if (wide_col) {
      std::memcpy(p, &q.column, 4);
      p += 4;
    } else {
      const auto c = static_cast<std::uint16_t>(q.column);
      std::memcpy(p, &c, 2);
      p += 2;
    }
    std::memcpy(p, &q.timestamp, 8);
    p += 8;
    ++n;
  }
  out.resize(start + n * record);
  return n;
}

void WriteTlsScanPly(const std::string& path, const TlsScan& scan) {
  if (scan.points.size() != static_cast<std::size_t>(scan.rows) * scan.columns) {
    throw InputError(path, "scan grid size mismatch",
                     std::to_string(scan.points.size()) + " points",
                     std::to_string(scan.rows) + " x " + std::to_string(scan.columns));
  }
  TlsPlyStreamWriter writer(path, scan);
  std::vector<TlsPoint> column(scan.rows);
  std::string bytes;
  for (std::uint32_t c = 0; c < scan.columns; ++c) {
    for (std::uint32_t r = 0; r < scan.rows; ++r) column[r] = scan.at(r, c);
    bytes.clear();
    const auto n =
        TlsPlyStreamWriter::EncodePoints(column, writer.wide_row(), writer.wide_col(), bytes);
    writer.Append(bytes, n);
  }
  writer.Close();
}

TlsScan ReadTlsScanPly(const std::string& path) {
  const PointCloud cloud = ReadPly(path);
  TlsScan scan;
  bool tagged = false, grid = false;
  for (const auto& c : cloud.comments) {
    std::istringstream ls(c);
    std::string key;
    ls >> key;
    if (key == "mopad_tls_scan")
      tagged = true;
    else if (key == "mopad_scan_id")
      ls >> scan.scan_id;
    else if (key == "mopad_start_time")
      ls >> scan.start_time;
    else if (key == "mopad_grid") {
      ls >> scan.rows >> scan.columns >> scan.azimuth_min >> scan.azimuth_step >>
          scan.elevation_max >> scan.elevation_step;
      grid = !ls.fail();
    } else if (key == "mopad_X_BS") {
      if (!ParsePoseWords(ls, &scan.X_BS)) throw InputError(path, "malformed mopad_X_BS comment");
    } else if (key == "mopad_X_MS_estimate") {
      if (!ParsePoseWords(ls, &scan.X_MS_estimate))
        throw InputError(path, "malformed mopad_X_MS_estimate comment");
    }
  }
  if (!tagged || !grid) throw InputError(path, "not a mopad TLS scan PLY (no mopad_grid comment)");
  const char* names[] = {"scalar_intensity", "scalar_range", "scalar_row", "scalar_column",
                         "scalar_timestamp"};
  const ScalarField* f[5];
  for (int i = 0; i < 5; ++i) {
    f[i] = cloud.Field(names[i]);
    if (!f[i]) throw InputError(path, std::string("missing property ") + names[i]);
  }
  if (cloud.colors.empty()) throw InputError(path, "missing red/green/blue");
  scan.points.assign(static_cast<std::size_t>(scan.rows) * scan.columns, TlsPoint{});
  for (std::uint32_t r = 0; r < scan.rows; ++r)
    for (std::uint32_t c = 0; c < scan.columns; ++c) {
      TlsPoint& p = scan.points[static_cast<std::size_t>(r) * scan.columns + c];
      p.row = r;
      p.column = c;
    }
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const auto r = static_cast<std::uint32_t>(f[2]->values[i]);
    const auto c = static_cast<std::uint32_t>(f[3]->values[i]);
    if (r >= scan.rows || c >= scan.columns) {
      throw InputError(path, "point " + std::to_string(i) + " outside the grid",
                       std::to_string(r) + "," + std::to_string(c));
    }
    TlsPoint& p = scan.points[static_cast<std::size_t>(r) * scan.columns + c];
    p.x = cloud.points[i].x();
    p.y = cloud.points[i].y();
    p.z = cloud.points[i].z();
    p.r = cloud.colors[i][0];
    p.g = cloud.colors[i][1];
    p.b = cloud.colors[i][2];
    p.intensity = static_cast<float>(f[0]->values[i]);
    p.range = static_cast<float>(f[1]->values[i]);
    p.timestamp = f[4]->values[i];
  }
  return scan;
}

// ---------------------------------------------------------------- PTX

namespace {

std::string PtxHeader(const TlsScan& s) {
  const Eigen::Matrix3d R = s.X_MS_estimate.linear();
  const Eigen::Vector3d t = s.X_MS_estimate.translation();
  std::string h = std::to_string(s.columns) + "\n" + std::to_string(s.rows) + "\n";
  auto line3 = [](const Eigen::Vector3d& v) {
    return FormatShortest(v.x()) + " " + FormatShortest(v.y()) + " " + FormatShortest(v.z());
  };
  h += line3(t) + "\n";
  for (int c = 0; c < 3; ++c) h += line3(R.col(c)) + "\n";  // scanner axes in the map frame
  // 4x4 in PTX's row-vector convention: rotation columns as rows, translation last.
  for (int c = 0; c < 3; ++c) h += line3(R.col(c)) + " 0\n";
  h += line3(t) + " 1\n";
  return h;
}

}  // namespace

TlsPtxStreamWriter::TlsPtxStreamWriter(const std::string& path, const TlsScan& meta)
    : path_(path), out_(path) {
  file_ = OpenForWrite(out_);
  const std::string h = PtxHeader(meta);
  WriteOrThrow(file_, h.data(), h.size(), path_);
}

TlsPtxStreamWriter::~TlsPtxStreamWriter() {
  if (file_) std::fclose(file_);
}

void TlsPtxStreamWriter::EncodeCells(std::span<const TlsPoint> cells, std::string& out) {
  char buf[512];  // 4 floats in fixed notation (<= 50 chars each for |v| < 1e38) + 3 bytes
  for (const TlsPoint& p : cells) {
    if (!p.valid()) {
      out += "0 0 0 0 0 0 0\n";
      continue;
    }
    char* e = buf;
    char* const end = buf + sizeof(buf) - 1;
    for (float v : {p.x, p.y, p.z, p.intensity}) {
      e = std::to_chars(e, end, v, std::chars_format::fixed, 5).ptr;
      if (e < end) *e++ = ' ';
    }
    for (std::uint8_t v : {p.r, p.g, p.b}) {
      e = std::to_chars(e, end, static_cast<int>(v)).ptr;
      if (e < end) *e++ = ' ';
    }
    e[-1] = '\n';
    out.append(buf, e);
  }
}

void TlsPtxStreamWriter::Append(const std::string& text) {
  WriteOrThrow(file_, text.data(), text.size(), path_);
}

void TlsPtxStreamWriter::Close() {
  if (!file_) return;
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) throw InputError(path_, "write failed", std::strerror(errno));
  out_.Commit();
}

void WriteTlsScanPtx(const std::string& path, const TlsScan& scan) {
  if (scan.points.size() != static_cast<std::size_t>(scan.rows) * scan.columns) {
    throw InputError(path, "scan grid size mismatch");
  }
  TlsPtxStreamWriter writer(path, scan);
  std::vector<TlsPoint> column(scan.rows);
  std::string text;
  for (std::uint32_t c = 0; c < scan.columns; ++c) {
    for (std::uint32_t r = 0; r < scan.rows; ++r) column[r] = scan.at(r, c);
    text.clear();
    TlsPtxStreamWriter::EncodeCells(column, text);
    writer.Append(text);
  }
  writer.Close();
}

TlsScan ReadTlsScanPtx(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open file");
  TlsScan scan;
  long long cols = 0, rows = 0;
  in >> cols >> rows;
  if (!in || cols <= 0 || rows <= 0)
    throw InputError(path + ":1", "malformed PTX header (columns, rows)");
  // Every cell is a line of at least four numbers ("0 0 0 0\n", 8 bytes): a header that claims
  // more cells than the file's bytes can hold is refused before the grid is allocated.
  constexpr std::uint64_t kMinCellBytes = 8;
  std::error_code size_error;
  const std::uint64_t file_bytes = std::filesystem::file_size(path, size_error);
  const std::uint64_t max_cells = size_error ? 0 : file_bytes / kMinCellBytes;
  const auto kMaxSide = static_cast<long long>(std::numeric_limits<std::uint32_t>::max());
  if (cols > kMaxSide || rows > kMaxSide ||
      static_cast<std::uint64_t>(cols) * static_cast<std::uint64_t>(rows) > max_cells)
    throw InputError(path + ":1", "PTX header claims more cells than the file holds",
                     std::to_string(cols) + " x " + std::to_string(rows),
                     "at most " + std::to_string(max_cells) + " cells in " +
                         std::to_string(file_bytes) + " bytes");
  double v[3 * 4 + 4 * 4];
  for (double& x : v) in >> x;
  if (!in) throw InputError(path, "malformed PTX header (pose)");
  Eigen::Matrix3d R;
  Eigen::Vector3d t(v[0], v[1], v[2]);
  for (int c = 0; c < 3; ++c) R.col(c) = Eigen::Vector3d(v[3 + 3 * c], v[4 + 3 * c], v[5 + 3 * c]);
  scan.X_MS_estimate.linear() = R;
  scan.X_MS_estimate.translation() = t;
  scan.rows = static_cast<std::uint32_t>(rows);
  scan.columns = static_cast<std::uint32_t>(cols);
  scan.points.assign(static_cast<std::size_t>(rows) * cols, TlsPoint{});
  std::string line;
  std::getline(in, line);  // rest of the last header line
  for (long long c = 0; c < cols; ++c) {
    for (long long r = 0; r < rows; ++r) {
      if (!std::getline(in, line))
        throw InputError(path, "PTX file truncated", "", std::to_string(rows * cols) + " cells");
      std::istringstream ls(line);
      double x, y, z, i;
      int cr = 0, cg = 0, cb = 0;
      ls >> x >> y >> z >> i;
      if (ls.fail()) throw InputError(path, "malformed PTX cell", "'" + line + "'");
      ls >> cr >> cg >> cb;
      TlsPoint& p = scan.points[static_cast<std::size_t>(r) * cols + c];
      p.row = static_cast<std::uint32_t>(r);
      p.column = static_cast<std::uint32_t>(c);
      p.x = static_cast<float>(x);
      p.y = static_cast<float>(y);
      p.z = static_cast<float>(z);
      p.intensity = static_cast<float>(i);
      p.r = static_cast<std::uint8_t>(cr);
      p.g = static_cast<std::uint8_t>(cg);
      p.b = static_cast<std::uint8_t>(cb);
      p.range = static_cast<float>(std::sqrt(x * x + y * y + z * z));
    }
  }
  return scan;
}

}  // namespace mopad::io
