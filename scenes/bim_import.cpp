#include "scenes/bim_import.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/error.h"
#include "common/format.h"
#include "common/frames.h"
#include "scenes/assimp_loader.h"
#include "scenes/bsc_catalogue.h"
#include "scenes/geometry.h"
#include "scenes/gltf_writer.h"
#include "scenes/scene_check.h"
#include "scenes/scene_loader.h"

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using Poly3 = std::vector<Vector3d>;

constexpr double kMinPieceArea = 1e-8;      // m^2: clipped slivers below this are dropped
constexpr double kLeafGap = 0.003;          // m, leaf-to-hole clearance (as the generator's)
constexpr double kFacingCos = 0.999;        // a face is parallel to a room plane (2.6 deg)
constexpr double kOpeningReach = 0.8;       // m: an opening's centre lies this deep behind a face
constexpr double kFarFromOrigin = 1e4;      // m: beyond this, float loses the millimetre
constexpr double kFullCover = 0.995;        // share of a room a floor/ceiling must cover
constexpr double kPassageTolerance = 0.01;  // m: two rooms' edges on one line
constexpr std::size_t kGuidLength = 22;     // IFC GlobalId, base64 of 128 bits

std::string Fmt(double v, int precision = 3) {
  if (std::abs(v) < 0.5 * std::pow(10.0, -precision)) v = 0.0;  // no "-0.000"
  return FormatFixed(v, precision);
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// --- STEP (ISO 10303-21) text: an index of entity instances, attributes, strings. ---

struct StepIndex {
  std::map<unsigned long, std::string> bodies;  // #id -> "IFCWALL('guid',#13,...)"
};

StepIndex IndexStep(const std::string& text) {
  StepIndex index;
  std::size_t i = text.find("DATA;");
  if (i == std::string::npos) return index;
  while ((i = text.find('#', i)) != std::string::npos) {
    std::size_t j = i + 1;
    while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j]))) ++j;
    if (j == i + 1) {
      ++i;
      continue;
    }
    const unsigned long id = std::stoul(text.substr(i + 1, j - i - 1));
    std::size_t k = j;
    while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
    if (k >= text.size() || text[k] != '=') {
      i = j;
      continue;
    }
    ++k;
    while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
    bool quoted = false;
    std::size_t e = k;
    for (; e < text.size(); ++e) {
      if (text[e] == '\'')
        quoted = !quoted;
      else if (text[e] == ';' && !quoted)
        break;
    }
    index.bodies[id] = text.substr(k, e - k);
    i = e;
  }
  return index;
}

std::string EntityOf(const std::string& body) {
  std::size_t n = 0;
  while (n < body.size() && (std::isalnum(static_cast<unsigned char>(body[n])) || body[n] == '_'))
    ++n;
  std::string s = body.substr(0, n);
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Top-level attributes of "ENTITY(a,b,(c,d),'e,f')".
std::vector<std::string> Attributes(const std::string& body) {
  std::vector<std::string> out;
  const std::size_t open = body.find('(');
  if (open == std::string::npos) return out;
  int depth = 0;
  bool quoted = false;
  std::string cur;
  for (std::size_t i = open + 1; i < body.size(); ++i) {
    const char c = body[i];
    if (c == '\'') quoted = !quoted;
    if (!quoted) {
      if (c == '(') ++depth;
      if (c == ')') {
        if (depth == 0) break;
        --depth;
      }
      if (c == ',' && depth == 0) {
        out.push_back(cur);
        cur.clear();
        continue;
      }
    }
    cur += c;
  }
  out.push_back(cur);
  for (auto& a : out) {
    while (!a.empty() && std::isspace(static_cast<unsigned char>(a.front()))) a.erase(a.begin());
    while (!a.empty() && std::isspace(static_cast<unsigned char>(a.back()))) a.pop_back();
  }
  return out;
}

void AppendUtf8(unsigned cp, std::string* out) {
  if (cp < 0x80) {
    *out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    *out += static_cast<char>(0xC0 | (cp >> 6));
    *out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    *out += static_cast<char>(0xE0 | (cp >> 12));
    *out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    *out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

// A STEP string literal 'Eingangst\S\|r' decoded to UTF-8 ('' quotes, \S\ Latin-1, \X2\ UTF-16);
// "" for $ or a non-string.
std::string StepString(const std::string& attr) {
  if (attr.size() < 2 || attr.front() != '\'' || attr.back() != '\'') return "";
  const std::string s = attr.substr(1, attr.size() - 2);
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\'' && i + 1 < s.size() && s[i + 1] == '\'') {
      out += '\'';
      ++i;
    } else if (s.compare(i, 3, "\\S\\") == 0 && i + 3 < s.size()) {
      AppendUtf8(static_cast<unsigned char>(s[i + 3]) + 0x80u, &out);
      i += 3;
    } else if (s.compare(i, 4, "\\X2\\") == 0) {
      std::size_t j = i + 4;
      while (j + 4 <= s.size() && s.compare(j, 4, "\\X0\\") != 0) {
        AppendUtf8(static_cast<unsigned>(std::strtoul(s.substr(j, 4).c_str(), nullptr, 16)), &out);
        j += 4;
      }
      i = j + 3;
    } else {
      out += s[i];
    }
  }
  return out;
}

// Metres per file length unit, all of it (SI prefix and conversion factor): for attributes
// read from the STEP text (assimp applies the prefix to geometry itself).
double FullLengthScale(const std::string& text, const StepIndex& index, const std::string& where) {
  const double unapplied = IfcUnappliedLengthScale(text, where);
  for (const auto& [id, body] : index.bodies) {
    if (EntityOf(body) != "IFCUNITASSIGNMENT") continue;
    for (std::size_t p = body.find('#'); p != std::string::npos; p = body.find('#', p + 1)) {
      const auto it = index.bodies.find(std::strtoul(body.c_str() + p + 1, nullptr, 10));
      if (it == index.bodies.end() || it->second.find(".LENGTHUNIT.") == std::string::npos)
        continue;
      if (EntityOf(it->second) != "IFCSIUNIT") return unapplied;
      static const std::pair<const char*, double> kPrefixes[] = {
          {".KILO.", 1e3},   {".HECTO.", 1e2},  {".DECA.", 1e1},  {".DECI.", 1e-1},
          {".CENTI.", 1e-2}, {".MILLI.", 1e-3}, {".MICRO.", 1e-6}};
      for (const auto& [name, s] : kPrefixes)
        if (it->second.find(name) != std::string::npos) return s;
      return 1.0;
    }
    break;
  }
  return unapplied;
}

std::string ReadText(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot open file", "unreadable", "a readable file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// --- node names: `<IfcClass>_<Name without spaces>_<GlobalId>` ---

std::string NodeGuid(const std::string& node) {
  if (node.size() < kGuidLength + 2 || node[node.size() - kGuidLength - 1] != '_') return "";
  return node.substr(node.size() - kGuidLength);
}

std::string NodeLabel(const std::string& node) {
  const std::size_t first = node.find('_');
  if (first == std::string::npos) return node;
  const std::string guid = NodeGuid(node);
  const std::size_t end = guid.empty() ? node.size() : node.size() - kGuidLength - 1;
  return end > first ? node.substr(first + 1, end - first - 1) : "";
}

// Valid UTF-8 for ids and names written to JSON and glTF: invalid bytes (Latin-1 names some
// IFC writers leave in STEP strings) become '?'.
std::string CleanUtf8(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const int n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    bool ok = n > 0 && i + n <= s.size() && !(n == 1 && c < 0x20);
    for (int k = 1; ok && k < n; ++k) ok = (static_cast<unsigned char>(s[i + k]) >> 6) == 2;
    if (ok) {
      out.append(s, i, static_cast<std::size_t>(n));
      i += static_cast<std::size_t>(n);
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

std::string NoSpaces(std::string s) {
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c) != 0; }),
          s.end());
  return s;
}

// --- convex polygon clipping in 3D (the pieces stay exactly on their original plane) ---

struct HalfSpace {
  Vector3d n;  // inside: n . x <= c
  double c;
};

Poly3 Clip(const Poly3& poly, const Vector3d& n, double c) {
  Poly3 out;
  const std::size_t k = poly.size();
  for (std::size_t i = 0; i < k; ++i) {
    const Vector3d& p = poly[i];
    const Vector3d& q = poly[(i + 1) % k];
    const double dp = n.dot(p) - c, dq = n.dot(q) - c;
    if (dp <= 0.0) out.push_back(p);
    if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0))
      out.push_back(p + dp / (dp - dq) * (q - p));
  }
  return out;
}

double Area(const Poly3& p) {
  if (p.size() < 3) return 0.0;
  Vector3d s = Vector3d::Zero();
  for (std::size_t i = 1; i + 1 < p.size(); ++i) s += (p[i] - p[0]).cross(p[i + 1] - p[0]);
  return 0.5 * s.norm();
}

// A piece worth keeping: not a float-noise sliver (area or width under ~1 um).
bool Solid(const Poly3& p) {
  const double area = Area(p);
  if (area <= kMinPieceArea) return false;
  double perimeter = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) perimeter += (p[(i + 1) % p.size()] - p[i]).norm();
  return area > 1e-6 * perimeter;
}

// poly = inside + sum(outside): inside = poly within all half-spaces (empty if a sliver).
void Split(const Poly3& poly, const std::vector<HalfSpace>& region, Poly3* inside,
           std::vector<Poly3>* outside) {
  Poly3 rest = poly;
  for (const HalfSpace& h : region) {
    Poly3 out = Clip(rest, -h.n, -h.c);
    if (Solid(out)) outside->push_back(std::move(out));
    rest = Clip(rest, h.n, h.c);
    if (!Solid(rest)) {
      inside->clear();
      return;
    }
  }
  *inside = std::move(rest);
}

Vector3d NormalOf(const Poly3& p) {
  Vector3d s = Vector3d::Zero();
  for (std::size_t i = 1; i + 1 < p.size(); ++i) s += (p[i] - p[0]).cross(p[i + 1] - p[0]);
  const double n = s.norm();
  return n > 0.0 ? Vector3d(s / n) : Vector3d::Zero();
}

// --- the output: buckets of pieces, one MeshPart each, in order of creation ---

struct Bucket {
  std::string name, id, subclass, room;
  ElementClass cls = ElementClass::kOther;
  int material = -1;
  std::vector<Poly3> pieces;
};

class Output {
 public:
  Bucket& Get(const std::string& id, ElementClass cls, const std::string& subclass,
              const std::string& room, int material, const std::string& name = "") {
    const std::string key = id + "\x1f" + std::to_string(static_cast<int>(cls)) + "\x1f" +
                            subclass + "\x1f" + room + "\x1f" + std::to_string(material);
    auto it = index_.find(key);
    if (it == index_.end()) {
      it = index_.emplace(key, buckets_.size()).first;
      Bucket b;
      b.id = id;
      b.cls = cls;
      b.subclass = subclass;
      b.room = room;
      b.material = material;
      b.name = (name.empty() ? id : name) + "/" + std::to_string(buckets_.size());
      buckets_.push_back(std::move(b));
    }
    return buckets_[it->second];
  }
  std::vector<Bucket>& buckets() { return buckets_; }

  std::vector<MeshPart> Parts() const {
    std::vector<MeshPart> parts;
    for (const Bucket& b : buckets_) {
      if (b.pieces.empty()) continue;
      MeshPart p;
      p.name = b.name;
      p.element_id = b.id;
      p.element_class = b.cls;
      p.subclass = b.subclass;
      p.room = b.room;
      p.material = b.material;
      std::map<std::array<float, 3>, int> vertex;
      auto v = [&](const Vector3d& x) {
        const std::array<float, 3> key{static_cast<float>(x.x()), static_cast<float>(x.y()),
                                       static_cast<float>(x.z())};
        auto [it, fresh] = vertex.emplace(key, static_cast<int>(p.positions.size()));
        if (fresh) p.positions.emplace_back(key[0], key[1], key[2]);
        return it->second;
      };
      for (const Poly3& poly : b.pieces)
        for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
          const Eigen::Vector3i t(v(poly[0]), v(poly[i]), v(poly[i + 1]));
          if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) p.triangles.push_back(t);
        }
      if (!p.triangles.empty()) parts.push_back(std::move(p));
    }
    return parts;
  }

 private:
  std::vector<Bucket> buckets_;
  std::map<std::string, std::size_t> index_;
};

// --- what an IFC element becomes ---

enum class Role { kSpace, kWall, kSlab, kColumn, kDoor, kWindow, kComponent, kFurniture, kOther };

// Catalogue class of a component IFC class ("" = not a component class). Sizes pick sockets.
std::string ComponentClass(const std::string& ifc, const std::string& type_class,
                           const Eigen::Vector3d& size) {
  // IFC 2x3 has no IfcOutlet or IfcSwitchingDevice: a generic IfcFlowTerminal/IfcFlowController
  // says what it is through its type object (IfcOutletType -> "ifcoutlet").
  const std::string c = type_class.empty() ? Lower(ifc) : type_class;
  if (c == "ifcoutlet") {
    const double w = std::max(size.x(), size.y());
    return w < 0.12 ? "socket_x1" : w < 0.22 ? "socket_x2" : "socket_x4";
  }
  if (c == "ifcswitchingdevice") return "switch";
  if (c == "ifcalarm") return "fire_alarm_switch";
  if (c == "ifcelectricdistributionpoint" || c == "ifcelectricdistributionboard")
    return "electrical_panel";
  if (c == "ifcspaceheater") return "radiator";
  if (c == "ifcsensor") return "smoke_detector";  // kept only when ceiling-mounted (below)
  if (!type_class.empty() && c != Lower(ifc)) return ComponentClass(ifc, "", size);
  return "other:" + ifc;
}

bool IsComponentIfc(const std::string& ifc) {
  const std::string c = Lower(ifc);
  static const std::set<std::string> kNames = {"ifcoutlet",
                                               "ifcswitchingdevice",
                                               "ifcalarm",
                                               "ifcsensor",
                                               "ifcactuator",
                                               "ifcfiresuppressionterminal",
                                               "ifclightfixture",
                                               "ifclamp",
                                               "ifcflowterminal",
                                               "ifcelectricdistributionpoint",
                                               "ifcelectricdistributionboard",
                                               "ifcspaceheater",
                                               "ifcairterminal",
                                               "ifcsanitaryterminal",
                                               "ifcstackterminal",
                                               "ifcwasteterminal",
                                               "ifccommunicationsappliance",
                                               "ifcaudiovisualappliance",
                                               "ifcprotectivedevice",
                                               "ifcunitaryequipment",
                                               "ifcflowcontroller",
                                               "ifcdistributioncontrolelement",
                                               "ifcbuildingelementproxy",
                                               "ifcdiscreteaccessory",
                                               "ifcsignal"};
  return kNames.count(c) > 0;
}

Role RoleOf(const std::string& ifc, ElementClass cls) {
  const std::string c = Lower(ifc);
  // Air: space volumes, and opening volumes when a converter kept them (assimp does not).
  if (cls == ElementClass::kSpace || c == "ifcopeningelement" || c == "ifcvirtualelement")
    return Role::kSpace;
  if (cls == ElementClass::kWall) return Role::kWall;
  if (cls == ElementClass::kSlab || cls == ElementClass::kCeiling || cls == ElementClass::kRoof ||
      cls == ElementClass::kFloor)
    return Role::kSlab;
  if (cls == ElementClass::kColumn) return Role::kColumn;
  if (c == "ifcdoor" || c == "ifcdoorstandardcase") return Role::kDoor;
  if (c == "ifcwindow" || c == "ifcwindowstandardcase") return Role::kWindow;
  if (cls == ElementClass::kFurniture) return Role::kFurniture;
  if (IsComponentIfc(ifc)) return Role::kComponent;
  return Role::kOther;
}

struct Element {
  std::string node;  // node name = id of its leftovers
  std::string ifc;   // IFC class
  std::vector<std::size_t> parts;
  Eigen::AlignedBox3d box;
  bool in_storey = false;
  bool merged = false;
  Role role = Role::kOther;
};

struct RoomData {
  Room room;
  std::string node;
  Polygon2 poly;
  std::vector<Eigen::Vector3i> ears;
};

struct Face {
  int room = -1;
  int edge = -1;
  std::string id;
  Vector3d a, dir, n;  // edge start at the room's floor, unit direction, unit inward normal
  double length = 0.0, z0 = 0.0, z1 = 0.0;
  std::vector<std::pair<std::size_t, Poly3>> pieces;  // (element, piece)
  std::vector<int> materials;                         // per piece
  double umin = 0.0, umax = 0.0, vmin = 0.0, vmax = 0.0, area = 0.0;
  bool kept = false;
  double U(const Vector3d& p) const { return (p - a).dot(dir); }
  double W(const Vector3d& p) const { return (p - a).dot(n); }
  std::vector<HalfSpace> Region() const {
    return {{-dir, -dir.dot(a)},
            {dir, dir.dot(a) + length},
            {-Vector3d::UnitZ(), -z0},
            {Vector3d::UnitZ(), z1}};
  }
};

// Coverage of the face's pieces along the line v = const (horizontal, by = false) or
// u = const (vertical): merged intervals of the other coordinate.
std::vector<std::pair<double, double>> Coverage(const Face& f, bool vertical, double at) {
  std::vector<std::pair<double, double>> iv;
  for (const auto& [e, poly] : f.pieces) {
    double lo = 1e300, hi = -1e300;
    const std::size_t k = poly.size();
    for (std::size_t i = 0; i < k; ++i) {
      const Vector3d& p = poly[i];
      const Vector3d& q = poly[(i + 1) % k];
      const double sp = vertical ? f.U(p) : p.z(), sq = vertical ? f.U(q) : q.z();
      const double op = vertical ? p.z() : f.U(p), oq = vertical ? q.z() : f.U(q);
      if ((sp - at) * (sq - at) > 0.0) continue;
      if (sp == sq) {
        lo = std::min({lo, op, oq});
        hi = std::max({hi, op, oq});
        continue;
      }
      const double t = (at - sp) / (sq - sp);
      const double o = op + t * (oq - op);
      lo = std::min(lo, o);
      hi = std::max(hi, o);
    }
    if (lo < hi) iv.emplace_back(lo, hi);
  }
  std::sort(iv.begin(), iv.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& i : iv) {
    if (!merged.empty() && i.first <= merged.back().second + 1e-5)
      merged.back().second = std::max(merged.back().second, i.second);
    else
      merged.push_back(i);
  }
  return merged;
}

// The uncovered interval around `x` within [lo, hi]; false if x is covered.
bool GapAround(const std::vector<std::pair<double, double>>& cov, double x, double lo, double hi,
               double* g0, double* g1) {
  *g0 = lo;
  *g1 = hi;
  for (const auto& [a, b] : cov) {
    if (a <= x && x <= b) return false;
    if (b < x) *g0 = std::max(*g0, b);
    if (a > x) *g1 = std::min(*g1, a);
  }
  return *g1 > *g0;
}

// The outline of a space's bottom face (triangles facing down at its lowest z), CCW from above.
bool Footprint(const std::vector<Poly3>& tris, double z_min, double tol, Polygon2* out,
               std::string* why) {
  // The bottom face's triangles in plan (seen from above a downward face runs clockwise: the
  // boundary takes any winding). T-junctions, common in BRep spaces, are split there.
  std::vector<std::vector<Vector2d>> faces;
  for (const Poly3& t : tris) {
    if (NormalOf(t).z() > -kFacingCos) continue;
    bool low = true;
    for (const auto& p : t) low = low && std::abs(p.z() - z_min) <= tol;
    if (!low) continue;
    faces.push_back({t[0].head<2>(), t[1].head<2>(), t[2].head<2>()});
  }
  const TiledBoundary boundary = BoundaryOfTiledPolygons(faces, 1e-4);
  if (boundary.problem == TiledBoundary::kTouchesItself) {
    *why = "its bottom outline touches itself";
    return false;
  }
  if (boundary.problem == TiledBoundary::kNotClosed) {
    *why = "its bottom outline is not closed";
    return false;
  }
  if (boundary.loops.empty()) {
    *why = "no downward face at its lowest point";
    return false;
  }
  // The largest loop is the outline.
  Polygon2 best;
  for (const auto& loop : boundary.loops)
    if (std::abs(SignedArea(loop)) > std::abs(SignedArea(best))) best = loop;
  // Drop collinear vertices.
  for (bool changed = true; changed && best.size() > 3;) {
    changed = false;
    for (std::size_t i = 0; i < best.size() && best.size() > 3; ++i) {
      const Vector2d& p = best[(i + best.size() - 1) % best.size()];
      const Vector2d& c = best[i];
      const Vector2d& n = best[(i + 1) % best.size()];
      const Vector2d d1 = c - p, d2 = n - c;
      if (std::abs(d1.x() * d2.y() - d1.y() * d2.x()) <= 1e-6 * d1.norm() * d2.norm() + 1e-12) {
        best.erase(best.begin() + static_cast<long>(i));
        changed = true;
        break;
      }
    }
  }
  if (SignedArea(best) < 0.0) std::reverse(best.begin(), best.end());
  // Start at the lowest-leftmost vertex: independent of the file's vertex order.
  std::size_t s = 0;
  for (std::size_t i = 1; i < best.size(); ++i)
    if (best[i].y() < best[s].y() - 1e-9 ||
        (std::abs(best[i].y() - best[s].y()) <= 1e-9 && best[i].x() < best[s].x()))
      s = i;
  std::rotate(best.begin(), best.begin() + static_cast<long>(s), best.end());
  if (!IsSimplePolygon(best, why)) return false;
  if (boundary.loops.size() > 1)
    *why = std::to_string(boundary.loops.size()) + " outlines; the largest is used";
  *out = best;
  return true;
}

Vector3d Lift(const Vector2d& p, double z) { return {p.x(), p.y(), z}; }

class Importer {
 public:
  Importer(const std::string& path, const BimImportParams& params) : path_(path), p_(params) {}

  BimImport Run() {
    p_.Validate();
    Load();
    SelectStorey();
    MakeRooms();
    ResolveHeights();
    Shift();
    MakeFaces();
    DistributeStructure();
    FinishFaces();
    FloorsAndCeilings();
    Columns();
    Openings();
    Passages();
    Components();
    Finish();
    return std::move(out_);
  }

 private:
  // --- loading ---
  void Load() {
    LoadOptions lo;
    lo.import_ifc_spaces = true;
    scene_ = LoadScene(path_, lo);
    const std::string ext = Lower(std::filesystem::path(path_).extension().string());
    if (ext == ".ifc") ReadStepInfo(path_);
    std::set<std::string> own_ids;
    for (const MeshPart& part : scene_.parts) own_ids.insert(part.element_id);
    for (const std::string& m : p_.merge) {
      const Scene other = LoadScene(m, lo);
      if (Lower(std::filesystem::path(m).extension().string()) == ".ifc") ReadStepInfo(m);
      const int offset = static_cast<int>(scene_.materials.size());
      for (const Material& mat : other.materials) scene_.materials.push_back(mat);
      const int tex_offset = static_cast<int>(scene_.textures.size());
      for (const Texture& t : other.textures) scene_.textures.push_back(t);
      for (std::size_t k = offset; k < scene_.materials.size(); ++k)
        if (scene_.materials[k].base_color_texture >= 0)
          scene_.materials[k].base_color_texture += tex_offset;
      std::size_t taken = 0, known = 0;
      for (MeshPart part : other.parts) {
        const Role r = RoleOf(part.subclass, part.element_class);
        if (r != Role::kComponent && r != Role::kFurniture) continue;
        if (own_ids.count(part.element_id)) {  // the same GlobalId: the same element
          ++known;
          continue;
        }
        if (part.material >= 0) part.material += offset;
        merged_parts_.insert(scene_.parts.size());
        scene_.parts.push_back(std::move(part));
        ++taken;
      }
      out_.report.push_back("merge " + m + ": " + std::to_string(taken) +
                            " component/furniture part(s) taken, " + std::to_string(known) +
                            " already in the model, the rest of that model ignored");
    }
    // Elements in order of first appearance.
    std::map<std::string, std::size_t> index;
    for (std::size_t i = 0; i < scene_.parts.size(); ++i) {
      const MeshPart& part = scene_.parts[i];
      const std::string id = part.element_id.empty() ? "unlabelled" : CleanUtf8(part.element_id);
      auto [it, fresh] = index.emplace(id, elements_.size());
      if (fresh) {
        Element e;
        e.node = id;
        e.ifc = part.subclass;
        e.role = RoleOf(part.subclass, part.element_class);
        elements_.push_back(e);
      }
      Element& e = elements_[it->second];
      e.parts.push_back(i);
      e.merged = e.merged || merged_parts_.count(i) > 0;
      for (const auto& v : part.positions) e.box.extend(v.cast<double>());
    }
  }

  // Names, type objects and storey spaces from an IFC file's STEP text (GlobalId keyed).
  void ReadStepInfo(const std::string& path) {
    const std::string text = ReadText(path);
    const StepIndex step = IndexStep(text);
    std::map<unsigned long, std::string> guid_of;
    for (const auto& [id, body] : step.bodies) {
      const std::vector<std::string> a = Attributes(body);
      if (a.size() < 3) continue;
      const std::string guid = StepString(a[0]);
      if (guid.size() != kGuidLength) continue;
      guid_of[id] = guid;
      names_[guid] = StepString(a[2]);
    }
    auto refs = [](const std::string& list) {
      std::vector<unsigned long> out;
      for (std::size_t q = list.find('#'); q != std::string::npos; q = list.find('#', q + 1))
        out.push_back(std::strtoul(list.c_str() + q + 1, nullptr, 10));
      return out;
    };
    // Georeferenced coordinates: assimp 5.2.5 computes IFC geometry partly in float.
    double far = 0.0;
    for (const auto& [id, body] : step.bodies) {
      if (body.compare(0, 17, "IFCCARTESIANPOINT") != 0) continue;
      const std::size_t open = body.find("((");
      if (open == std::string::npos) continue;
      const char* c = body.c_str() + open + 2;
      for (int k = 0; k < 3; ++k) {
        char* end = nullptr;
        const double v = std::strtod(c, &end);
        if (end == c) break;
        if (std::isfinite(v)) far = std::max(far, std::abs(v));
        c = end;
        while (*c == ',' || *c == ' ') ++c;
      }
    }
    far *= FullLengthScale(text, step, path);
    if (far > kFarFromOrigin)
      out_.report.push_back(path + ": coordinates reach " + Fmt(far / 1000.0, 1) +
                            " km from the origin (georeferenced); assimp 5.2.5 computes IFC "
                            "geometry partly in float: expect errors of " +
                            Fmt(far * 1.2e-7 * 1000.0, 0) + " mm or more");
    for (const auto& [id, body] : step.bodies) {
      const std::string entity = EntityOf(body);
      const std::vector<std::string> a = Attributes(body);
      if (entity == "IFCRELDEFINESBYTYPE" && a.size() >= 6) {
        // (guid, owner, name, description, (#objects), #type)
        const auto type = step.bodies.find(refs(a[5]).empty() ? 0 : refs(a[5])[0]);
        if (type == step.bodies.end()) continue;
        std::string cls = Lower(EntityOf(type->second));
        if (cls.size() > 4 && cls.compare(cls.size() - 4, 4, "type") == 0)
          cls.resize(cls.size() - 4);
        for (unsigned long o : refs(a[4]))
          if (guid_of.count(o)) type_class_[guid_of[o]] = cls;
      } else if (entity == "IFCRELCONTAINEDINSPATIALSTRUCTURE" && a.size() >= 6) {
        // (guid, owner, name, description, (#elements), #structure)
        const std::vector<unsigned long> where = refs(a[5]);
        if (where.empty() || !guid_of.count(where[0])) continue;
        for (unsigned long o : refs(a[4]))
          if (guid_of.count(o) && step.bodies.count(o))
            storey_contained_[guid_of[where[0]]].emplace_back(guid_of[o],
                                                              EntityOf(step.bodies.at(o)));
      } else if (entity == "IFCRELAGGREGATES" && a.size() >= 6) {
        // (guid, owner, name, description, #relating, (#related)): spaces of a storey.
        const std::vector<unsigned long> whole = refs(a[4]);
        if (whole.empty() || !step.bodies.count(whole[0]) ||
            EntityOf(step.bodies.at(whole[0])) != "IFCBUILDINGSTOREY")
          continue;
        for (unsigned long o : refs(a[5]))
          if (step.bodies.count(o) && EntityOf(step.bodies.at(o)) == "IFCSPACE" &&
              guid_of.count(o) && guid_of.count(whole[0]))
            storey_spaces_[guid_of[whole[0]]].push_back(guid_of[o]);
      }
    }
  }

  std::string NiceName(const std::string& node) const {
    const auto it = names_.find(NodeGuid(node));
    const std::string n = it != names_.end() && !it->second.empty() ? it->second : NodeLabel(node);
    return IfcClassFromNodeName(node) + " '" + n + "'";
  }

  // Storey node segments of a part's node path (assimp: "a/b/IfcBuildingStorey_x_guid/...").
  static std::string StoreyOf(const std::string& node_path) {
    std::size_t start = 0;
    while (start <= node_path.size()) {
      std::size_t end = node_path.find('/', start);
      if (end == std::string::npos) end = node_path.size();
      const std::string seg = node_path.substr(start, end - start);
      if (IfcClassFromNodeName(seg) == "IfcBuildingStorey") return seg;
      start = end + 1;
    }
    return "";
  }

  void SelectStorey() {
    // Storeys in order of first appearance, with their lowest element.
    std::vector<std::string> storeys;
    std::map<std::string, double> low;
    for (std::size_t i = 0; i < scene_.parts.size(); ++i) {
      if (merged_parts_.count(i)) continue;
      const std::string s = StoreyOf(scene_.parts[i].name);
      if (s.empty()) continue;
      if (!low.count(s)) {
        storeys.push_back(s);
        low[s] = 1e300;
      }
      for (const auto& v : scene_.parts[i].positions) low[s] = std::min(low[s], double(v.z()));
    }
    std::sort(storeys.begin(), storeys.end(), [&](const std::string& a, const std::string& b) {
      return low[a] != low[b] ? low[a] < low[b] : a < b;
    });
    if (storeys.empty()) {
      if (!p_.storey.empty())
        throw InputError(path_, "the model names no storeys (no IfcBuildingStorey node paths)",
                         "--storey " + p_.storey, "no --storey for this file");
      out_.report.push_back(
          "no IfcBuildingStorey in the node paths: the whole model is one "
          "storey");
    } else if (p_.storey.empty()) {
      // The lowest storey with a space volume (foundation or site levels often have none).
      std::set<std::string> with_spaces;
      for (std::size_t i = 0; i < scene_.parts.size(); ++i)
        if (!merged_parts_.count(i) && scene_.parts[i].element_class == ElementClass::kSpace &&
            !scene_.parts[i].triangles.empty())
          with_spaces.insert(StoreyOf(scene_.parts[i].name));
      storey_ = storeys.front();
      for (const std::string& st : storeys)
        if (with_spaces.count(st)) {
          storey_ = st;
          break;
        }
      if (storeys.size() > 1)
        out_.report.push_back("storey " + StoreyName(storey_) + " (the lowest with spaces of " +
                              std::to_string(storeys.size()) + "; choose with --storey)");
    } else {
      std::string names;
      for (const std::string& s : storeys) {
        const std::string full = StoreyName(s);
        if (p_.storey == full || p_.storey == NodeLabel(s) || p_.storey == NodeGuid(s) ||
            p_.storey == s || NoSpaces(p_.storey) == NodeLabel(s))
          storey_ = s;
        names += (names.empty() ? "" : ", ") + std::string("'") + full + "'";
      }
      if (storey_.empty())
        throw InputError(path_, "no such storey", "'" + p_.storey + "'", "one of " + names);
    }
    const std::string guid = NodeGuid(storey_);
    out_.truth.storeys.push_back(
        {storey_.empty() ? "storey_0" : CleanUtf8(NoSpaces(StoreyName(storey_))), 0.0, 3.0});
    for (std::size_t i = 0; i < storeys.size(); ++i)
      if (storeys[i] == storey_ && i + 1 < storeys.size()) next_storey_low_ = low[storeys[i + 1]];
    for (std::size_t i = 0; i < scene_.parts.size(); ++i)
      if (storey_.empty() || StoreyOf(scene_.parts[i].name) == storey_) storey_parts_.insert(i);
    for (Element& e : elements_)
      for (std::size_t i : e.parts) e.in_storey = e.in_storey || storey_parts_.count(i) > 0;
  }

  std::string StoreyName(const std::string& node) const {
    const auto it = names_.find(NodeGuid(node));
    return it != names_.end() && !it->second.empty() ? it->second : NodeLabel(node);
  }

  std::vector<Poly3> Triangles(const Element& e) const {
    std::vector<Poly3> out;
    for (std::size_t i : e.parts) {
      const MeshPart& part = scene_.parts[i];
      for (const auto& t : part.triangles)
        out.push_back({part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                       part.positions[t[2]].cast<double>()});
    }
    return out;
  }

  void MakeRooms() {
    int spaces = 0;
    for (const Element& e : elements_) {
      if (e.role != Role::kSpace || !e.in_storey || Lower(e.ifc) != "ifcspace") continue;
      ++spaces;
      const std::vector<Poly3> tris = Triangles(e);
      if (tris.empty()) {
        out_.report.push_back(NiceName(e.node) + ": space without representation; no room");
        continue;
      }
      Polygon2 poly;
      std::string why;
      if (!Footprint(tris, e.box.min().z(), p_.plane_tolerance, &poly, &why)) {
        out_.report.push_back(NiceName(e.node) + ": no usable footprint (" + why + "); no room");
        continue;
      }
      if (!why.empty()) out_.report.push_back(NiceName(e.node) + ": " + why);
      RoomData r;
      r.node = e.node;
      r.poly = poly;
      r.room.id = "R" + std::to_string(rooms_.size() + 1);
      r.room.storey = out_.truth.storeys[0].id;
      r.room.floor_z = e.box.min().z();
      r.room.ceiling_z = e.box.max().z();
      rooms_.push_back(r);
      out_.report.push_back("room " + r.room.id + " = " + NiceName(e.node) + ", " +
                            std::to_string(poly.size()) + " corners, " + Fmt(SignedArea(poly), 2) +
                            " m2, height " + Fmt(r.room.ceiling_z - r.room.floor_z, 2) + " m");
    }
    // Spaces the STEP text puts on this storey that assimp gave no geometry at all.
    const auto listed = storey_spaces_.find(NodeGuid(storey_));
    if (listed != storey_spaces_.end())
      for (const std::string& guid : listed->second) {
        bool seen = false;
        for (const Element& e : elements_) seen = seen || NodeGuid(e.node) == guid;
        if (seen) continue;
        ++spaces;
        out_.report.push_back("IfcSpace '" + names_[guid] + "' (" + guid +
                              "): space without representation; no room");
      }
    // Elements the STEP text puts on this storey that assimp made no geometry for.
    static const std::set<std::string> kNoBody = {
        "IFCANNOTATION",       "IFCGRID",   "IFCVIRTUALELEMENT", "IFCOPENINGELEMENT", "IFCSPACE",
        "IFCDISTRIBUTIONPORT", "IFCSYSTEM", "IFCZONE",           "IFCGROUP",          "IFCPROXY"};
    const auto contained = storey_contained_.find(NodeGuid(storey_));
    if (contained != storey_contained_.end()) {
      std::set<std::string> with_geometry;
      for (const Element& e : elements_) with_geometry.insert(NodeGuid(e.node));
      for (const auto& [guid, entity] : contained->second)
        if (!kNoBody.count(entity) && !with_geometry.count(guid))
          out_.report.push_back(entity + " '" + CleanUtf8(names_[guid]) + "' (" + guid +
                                "): no geometry (assimp made none); left out");
    }
    if (rooms_.empty())
      throw InputError(path_,
                       storey_.empty()
                           ? std::string("no room can be made in the model")
                           : "no room can be made on storey '" + StoreyName(storey_) + "'",
                       std::to_string(spaces) + " IfcSpace(s), none with a usable volume",
                       "IfcSpace volumes (IFC 2x3, or glTF converted with its spaces kept)");
  }

  // Share of room r's footprint covered by slab faces facing up (down) at height z.
  double SlabCover(std::size_t r, double z, bool up) const {
    const RoomData& room = rooms_[r];
    const std::vector<Eigen::Vector3i> ears = TriangulatePolygon(room.poly);
    double area = 0.0;
    for (const Element& e : elements_) {
      if (e.role != Role::kSlab || e.box.min().z() > z + p_.plane_tolerance ||
          e.box.max().z() < z - p_.plane_tolerance)
        continue;
      for (std::size_t pi : e.parts) {
        const MeshPart& part = scene_.parts[pi];
        for (const auto& t : part.triangles) {
          const Poly3 tri{part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                          part.positions[t[2]].cast<double>()};
          const Vector3d n = NormalOf(tri);
          if (up ? n.z() < kFacingCos : n.z() > -kFacingCos) continue;
          bool on = true;
          for (const auto& q : tri) on = on && std::abs(q.z() - z) <= p_.plane_tolerance;
          if (!on) continue;
          for (const auto& ear : ears) {
            std::vector<HalfSpace> region;
            for (int k = 0; k < 3; ++k) {
              const Vector2d& a = room.poly[ear[k]];
              const Vector2d& b = room.poly[ear[(k + 1) % 3]];
              const Vector3d nn(b.y() - a.y(), -(b.x() - a.x()), 0.0);
              region.push_back({nn, nn.dot(Lift(a, 0.0))});
            }
            Poly3 in;
            std::vector<Poly3> outside;
            Split(tri, region, &in, &outside);
            area += Area(in);
          }
        }
      }
    }
    return area / SignedArea(room.poly);
  }

  // A space drawn into the slab above (to the next level, as some tools do) or short of the
  // ceiling: the room's ceiling (floor) is the fully covering slab face nearest to the space's
  // top (bottom), within [floor + 1.8 m, top + 1 m] ([bottom - 0.3 m, bottom + 0.3 m]).
  void ResolveHeights() {
    for (std::size_t r = 0; r < rooms_.size(); ++r) {
      Room& room = rooms_[r].room;
      for (bool up : {true, false}) {
        const double z_space = up ? room.floor_z : room.ceiling_z;
        if (SlabCover(r, z_space, up) >= kFullCover) continue;
        const double lo = up ? z_space - 0.3 : room.floor_z + 1.8;
        const double hi = up ? z_space + 0.3 : z_space + 1.0;
        // Candidate planes (mm): slab faces facing the right way over the room's box.
        Eigen::AlignedBox2d room_box;
        for (const auto& v : rooms_[r].poly) room_box.extend(v);
        std::set<long long> heights;
        for (const Element& e : elements_) {
          if (e.role != Role::kSlab) continue;
          for (std::size_t pi : e.parts) {
            const MeshPart& part = scene_.parts[pi];
            for (const auto& t : part.triangles) {
              const Poly3 tri{part.positions[t[0]].cast<double>(),
                              part.positions[t[1]].cast<double>(),
                              part.positions[t[2]].cast<double>()};
              const Vector3d n = NormalOf(tri);
              if ((up ? n.z() < kFacingCos : n.z() > -kFacingCos) || tri[0].z() < lo ||
                  tri[0].z() > hi)
                continue;
              Eigen::AlignedBox2d box;
              for (const auto& q : tri) box.extend(q.head<2>());
              if (box.intersects(room_box)) heights.insert(std::llround(tri[0].z() * 1000.0));
            }
          }
        }
        double best = 0.0, best_d = 1e300;
        for (long long h : heights) {
          // The exact height of that plane: a vertex's, not the rounded value.
          const double z = static_cast<double>(h) / 1000.0;
          const double d = std::abs(z - z_space);
          if (d < best_d && SlabCover(r, z, up) >= kFullCover) {
            best = z;
            best_d = d;
          }
        }
        if (best_d > 1e299) continue;  // FloorsAndCeilings refuses or repairs
        // Snap to the plane's own height (the vertices' mean within the tolerance).
        double sum = 0.0, n = 0.0;
        for (const Element& e : elements_) {
          if (e.role != Role::kSlab) continue;
          for (std::size_t pi : e.parts)
            for (const auto& v : scene_.parts[pi].positions)
              if (std::abs(v.z() - best) <= 1e-3) sum += v.z(), n += 1.0;
        }
        const double z = n > 0 ? sum / n : best;
        out_.report.push_back(NiceName(rooms_[r].node) + ": its " + (up ? "floor" : "ceiling") +
                              " is the slab face at z = " + Fmt(z) + " m, not the space's " +
                              (up ? "bottom" : "top") + " at " + Fmt(z_space) + " m");
        (up ? room.floor_z : room.ceiling_z) = z;
      }
    }
  }

  void Shift() {
    z0_ = 1e300;
    double top = -1e300;
    for (const RoomData& r : rooms_) {
      z0_ = std::min(z0_, r.room.floor_z);
      top = std::max(top, r.room.ceiling_z);
    }
    // The storey's elements, and from elsewhere what reaches into its height band: the slab
    // above (its underside is the ceiling), the site, elements of no storey.
    const double lo = z0_ - 0.01, hi = top + 0.01;
    for (Element& e : elements_) {
      if (IfcClassFromNodeName(e.node) == "IfcSite" && !p_.keep_site) {
        if (!e.parts.empty() && !e.box.isEmpty())
          out_.report.push_back(NiceName(e.node) + ": terrain left out (--keep-site keeps it)");
        e.in_storey = false;
        continue;
      }
      if (e.in_storey || e.role == Role::kSpace) continue;
      const bool slab = e.role == Role::kSlab || IfcClassFromNodeName(e.node) == "IfcBeam";
      const double zmin = e.box.min().z(), zmax = e.box.max().z();
      e.in_storey = zmax >= lo && (slab ? zmin <= hi : zmin < top - 0.01);
      if (e.merged) e.in_storey = zmax >= lo && zmin <= hi;
    }
    for (MeshPart& part : scene_.parts)
      for (auto& v : part.positions) v.z() = static_cast<float>(v.z() - z0_);
    for (Element& e : elements_)
      if (!e.box.isEmpty()) e.box.translate(Vector3d(0, 0, -z0_));
    for (RoomData& r : rooms_) {
      r.room.floor_z -= z0_;
      r.room.ceiling_z -= z0_;
      r.room.polygon = r.poly;
      r.ears = TriangulatePolygon(r.poly);
      top_ = std::max(top_, r.room.ceiling_z);
    }
    Storey& s = out_.truth.storeys[0];
    s.elevation = 0.0;
    s.height = next_storey_low_ < 1e299 ? next_storey_low_ - z0_ : top_;
    if (!(s.height > 0.0)) s.height = top_;
    out_.report.push_back("storey floor at z = " + Fmt(z0_) + " m in the file: moved to 0");
  }

  void MakeFaces() {
    for (std::size_t r = 0; r < rooms_.size(); ++r) {
      const Polygon2& poly = rooms_[r].poly;
      for (std::size_t k = 0; k < poly.size(); ++k) {
        Face f;
        f.room = static_cast<int>(r);
        f.edge = static_cast<int>(k);
        f.id = "wall_" + rooms_[r].room.id + "_" + std::to_string(k);
        const Vector2d a = poly[k], b = poly[(k + 1) % poly.size()];
        f.length = (b - a).norm();
        f.a = Lift(a, rooms_[r].room.floor_z);
        f.dir = Lift((b - a) / f.length, 0.0);
        f.n = Vector3d(-f.dir.y(), f.dir.x(), 0.0);
        f.z0 = rooms_[r].room.floor_z;
        f.z1 = rooms_[r].room.ceiling_z;
        faces_.push_back(f);
      }
    }
  }

  int MaterialOf(std::size_t part) const { return scene_.parts[part].material; }

  void Leftover(std::size_t e, int material, Poly3 piece) {
    const Element& el = elements_[e];
    out_bucket_.Get(el.node, ElementClass::kOther, el.ifc, "", material)
        .pieces.push_back(std::move(piece));
    other_ids_.insert(el.node);
  }

  // Faces on a room's wall planes onto its wall faces (from walls, and from whatever else
  // forms the wall surface: coverings, parts, proxies, curtain-wall plates); slab faces onto
  // floors and ceilings; the rest of these elements is `other`.
  void DistributeStructure() {
    for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
      const Element& e = elements_[ei];
      if (!e.in_storey ||
          (e.role != Role::kWall && e.role != Role::kSlab && e.role != Role::kOther))
        continue;
      for (std::size_t pi : e.parts) {
        const MeshPart& part = scene_.parts[pi];
        for (const auto& t : part.triangles) {
          std::vector<Poly3> rest{{part.positions[t[0]].cast<double>(),
                                   part.positions[t[1]].cast<double>(),
                                   part.positions[t[2]].cast<double>()}};
          const Vector3d n = NormalOf(rest[0]);
          if (n.isZero()) continue;
          if (std::abs(n.z()) < 1.0 - kFacingCos) {
            for (Face& f : faces_) {
              if (n.dot(f.n) < kFacingCos) continue;
              bool on = true;
              for (const auto& p : rest[0]) on = on && std::abs(f.W(p)) <= p_.plane_tolerance;
              if (!on) continue;
              std::vector<Poly3> next;
              for (const Poly3& piece : rest) {
                Poly3 in;
                Split(piece, f.Region(), &in, &next);
                if (!in.empty()) {
                  if (NormalOf(in).dot(f.n) < 0.0) std::reverse(in.begin(), in.end());
                  f.pieces.emplace_back(ei, std::move(in));
                  f.materials.push_back(part.material);
                }
              }
              rest = std::move(next);
              if (rest.empty()) break;
            }
          } else if (e.role == Role::kSlab) {
            for (std::size_t r = 0; r < rooms_.size() && !rest.empty(); ++r) {
              const RoomData& room = rooms_[r];
              const bool up = n.z() >= kFacingCos, down = n.z() <= -kFacingCos;
              if (!up && !down) break;
              const double z = up ? room.room.floor_z : room.room.ceiling_z;
              bool on = true;
              for (const auto& p : rest[0]) on = on && std::abs(p.z() - z) <= p_.plane_tolerance;
              if (!on) continue;
              for (const auto& ear : room.ears) {
                std::vector<HalfSpace> region;
                for (int k = 0; k < 3; ++k) {
                  const Vector2d& a = room.poly[ear[k]];
                  const Vector2d& b = room.poly[ear[(k + 1) % 3]];
                  // Inside a CCW ear: left of every edge, i.e. (b - a)^perp . (x - a) >= 0.
                  const Vector3d nn(b.y() - a.y(), -(b.x() - a.x()), 0.0);
                  region.push_back({nn, nn.dot(Lift(a, 0.0))});
                }
                std::vector<Poly3> next;
                for (const Poly3& piece : rest) {
                  Poly3 in;
                  Split(piece, region, &in, &next);
                  if (!in.empty()) {
                    // Front faces into the room (docs/scene-format.md), whatever the file did.
                    if ((NormalOf(in).z() > 0.0) != up) std::reverse(in.begin(), in.end());
                    const std::string id = (up ? "floor_" : "ceiling_") + room.room.id;
                    (up ? floor_area_ : ceiling_area_)[r] += Area(in);
                    out_bucket_
                        .Get(id, up ? ElementClass::kFloor : ElementClass::kCeiling, "",
                             room.room.id, part.material)
                        .pieces.push_back(std::move(in));
                  }
                }
                rest = std::move(next);
                if (rest.empty()) break;
              }
            }
          }
          for (Poly3& piece : rest) Leftover(ei, part.material, std::move(piece));
        }
      }
    }
  }

  void FinishFaces() {
    std::map<std::string, int> walls_per_room;
    for (Face& f : faces_) {
      f.area = 0.0;
      double umin = 1e300, umax = -1e300, vmin = 1e300, vmax = -1e300;
      for (const auto& [e, poly] : f.pieces) {
        f.area += Area(poly);
        for (const auto& p : poly) {
          umin = std::min(umin, f.U(p));
          umax = std::max(umax, f.U(p));
          vmin = std::min(vmin, p.z());
          vmax = std::max(vmax, p.z());
        }
      }
      const RoomData& room = rooms_[f.room];
      if (f.area < p_.min_face_area) {
        for (std::size_t i = 0; i < f.pieces.size(); ++i)
          Leftover(f.pieces[i].first, f.materials[i], f.pieces[i].second);
        f.pieces.clear();
        out_.report.push_back("room " + room.room.id + " edge " + std::to_string(f.edge) + " (" +
                              Fmt(f.length, 2) +
                              " m): no wall face on it (open to a "
                              "neighbour, or the wall is not on the space boundary)");
        continue;
      }
      f.kept = true;
      for (const auto& piece : f.pieces)
        if (elements_[piece.first].role == Role::kWall) walls_with_faces_.insert(piece.first);
      f.umin = umin;
      f.umax = umax;
      f.vmin = vmin;
      f.vmax = vmax;
      for (std::size_t i = 0; i < f.pieces.size(); ++i)
        out_bucket_.Get(f.id, ElementClass::kWall, "", room.room.id, f.materials[i])
            .pieces.push_back(f.pieces[i].second);
      StructuralElement w;
      w.id = f.id;
      w.element_class = ElementClass::kWall;
      w.rooms = {room.room.id};
      // The faces' own plane (within plane_tolerance of the room edge; 0 for most files).
      double offset = 0.0, weight = 0.0;
      for (const auto& [el, poly] : f.pieces) {
        const double a = Area(poly);
        for (const auto& p : poly) offset += a * f.W(p) / static_cast<double>(poly.size());
        weight += a;
      }
      offset = weight > 0.0 ? offset / weight : 0.0;
      w.origin = f.a + umin * f.dir + offset * f.n + Vector3d(0, 0, vmin - f.a.z());
      w.u_axis = f.dir;
      w.normal = f.n;
      w.length = umax - umin;
      w.height = vmax - vmin;
      const Vector3d up(0, 0, w.height);
      const Vector3d along = w.length * f.dir;
      w.polygons = {{w.origin, w.origin + up, w.origin + along + up, w.origin + along}};
      walls_.push_back(w);
      ++walls_per_room[room.room.id];
    }
  }

  void FloorsAndCeilings() {
    for (std::size_t r = 0; r < rooms_.size(); ++r) {
      const RoomData& room = rooms_[r];
      const double area = SignedArea(room.poly);
      for (bool up : {true, false}) {
        const double have = (up ? floor_area_ : ceiling_area_)[r];
        const bool repair = up ? p_.floor_from_spaces : p_.ceiling_from_spaces;
        const std::string what = up ? "floor" : "ceiling";
        const std::string id = what + "_" + room.room.id;
        const ElementClass cls = up ? ElementClass::kFloor : ElementClass::kCeiling;
        const double z = up ? room.room.floor_z : room.room.ceiling_z;
        if (have < kFullCover * area) {
          const std::string line = "room " + room.room.id + " (" + NiceName(room.node) +
                                   "): " + Fmt(100.0 * have / area, 1) + " % of its " + what +
                                   " has geometry at z = " + Fmt(z) + " m";
          if (!repair)
            throw InputError(path_, line, "",
                             "--" + what +
                                 "-from-spaces to make it from the "
                                 "space footprint");
          // Replace what there is by the whole footprint (same plane: nothing is lost).
          for (Bucket& b : out_bucket_.buckets())
            if (b.id == id) b.pieces.clear();
          Bucket& b = out_bucket_.Get(id, cls, "", room.room.id, RepairMaterial(up));
          for (const auto& ear : room.ears) {
            Poly3 tri{Lift(room.poly[ear[0]], z), Lift(room.poly[ear[1]], z),
                      Lift(room.poly[ear[2]], z)};
            if (!up) std::swap(tri[1], tri[2]);
            b.pieces.push_back(tri);
          }
          out_.report.push_back(line + ": made from the space footprint");
        }
        StructuralElement s;
        s.id = id;
        s.element_class = cls;
        s.rooms = {room.room.id};
        s.normal = up ? Vector3d::UnitZ() : Vector3d(-Vector3d::UnitZ());
        Poly3 poly;
        for (const auto& v : room.poly) poly.push_back(Lift(v, z));
        if (!up) std::reverse(poly.begin(), poly.end());
        s.polygons = {poly};
        (up ? floors_ : ceilings_).push_back(s);
      }
    }
  }

  int RepairMaterial(bool floor) {
    const std::string name = floor ? "repaired_floor" : "repaired_ceiling";
    for (std::size_t i = 0; i < scene_.materials.size(); ++i)
      if (scene_.materials[i].name == name) return static_cast<int>(i);
    Material m;
    m.name = name;
    m.base_color = floor ? Eigen::Vector4f(0.45f, 0.42f, 0.38f, 1.0f)
                         : Eigen::Vector4f(0.85f, 0.85f, 0.85f, 1.0f);
    scene_.materials.push_back(m);
    return static_cast<int>(scene_.materials.size()) - 1;
  }

  int RoomAt(const Vector3d& p) const {
    for (std::size_t r = 0; r < rooms_.size(); ++r)
      if (p.z() >= rooms_[r].room.floor_z - 0.05 && p.z() <= rooms_[r].room.ceiling_z + 0.05 &&
          PointInPolygon(p.head<2>(), rooms_[r].poly))
        return static_cast<int>(r);
    return -1;
  }

  void Columns() {
    for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
      const Element& e = elements_[ei];
      if (!e.in_storey || e.role != Role::kColumn) continue;
      const int r = RoomAt(e.box.center());
      if (r < 0) {
        for (std::size_t pi : e.parts) AllToLeftover(ei, pi);
        out_.report.push_back(NiceName(e.node) + ": not inside a room; kept as other");
        continue;
      }
      StructuralElement c;
      c.id = "column_" + rooms_[r].room.id + "_" + std::to_string(++columns_in_[r]);
      c.element_class = ElementClass::kColumn;
      c.rooms = {rooms_[r].room.id};
      // One polygon per side plane: its extent along the horizontal tangent and z.
      std::map<std::array<long long, 4>, std::pair<Vector3d, Eigen::AlignedBox2d>> sides;
      for (std::size_t pi : e.parts) {
        const MeshPart& part = scene_.parts[pi];
        Bucket& b =
            out_bucket_.Get(c.id, ElementClass::kColumn, "", rooms_[r].room.id, part.material);
        for (const auto& t : part.triangles) {
          const Poly3 tri{part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                          part.positions[t[2]].cast<double>()};
          b.pieces.push_back(tri);
          const Vector3d n = NormalOf(tri);
          if (n.isZero() || std::abs(n.z()) > 0.01) continue;
          const std::array<long long, 4> key{std::llround(n.x() * 1e3), std::llround(n.y() * 1e3),
                                             std::llround(n.dot(tri[0]) * 1e3), 0};
          const Vector3d tan(-n.y(), n.x(), 0.0);
          auto& side = sides[key];
          side.first = n;
          for (const auto& p : tri) side.second.extend(Vector2d(tan.dot(p), p.z()));
        }
      }
      for (const auto& [key, side] : sides) {
        const Vector3d n = side.first, tan(-n.y(), n.x(), 0.0);
        const Vector3d o = n * (double(key[2]) * 1e-3);
        const auto& bx = side.second;
        auto P = [&](double s, double z) { return Vector3d(o + s * tan + Vector3d(0, 0, z)); };
        // CCW seen from outside (along n): tan is to the right of... order
        // (s0,z0),(s1,z0),(s1,z1),(s0,z1).
        Poly3 q{P(bx.min().x(), bx.min().y()), P(bx.max().x(), bx.min().y()),
                P(bx.max().x(), bx.max().y()), P(bx.min().x(), bx.max().y())};
        if (NormalOf(q).dot(n) < 0) std::reverse(q.begin(), q.end());
        c.polygons.push_back(q);
      }
      columns_.push_back(c);
    }
  }

  void AllToLeftover(std::size_t ei, std::size_t pi) {
    const MeshPart& part = scene_.parts[pi];
    for (const auto& t : part.triangles)
      Leftover(ei, part.material,
               {part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                part.positions[t[2]].cast<double>()});
  }

  struct Hole {
    std::size_t face;
    double u0, u1, v0, v1;  // in the face's edge frame (u from f.a, v = z)
    double dist;
  };

  // Faces with a hole around the element's centre, nearest first.
  std::vector<Hole> HolesAround(const Element& e) const {
    const Vector3d c = e.box.center();
    std::vector<Hole> holes;
    for (std::size_t fi = 0; fi < faces_.size(); ++fi) {
      const Face& f = faces_[fi];
      if (!f.kept) continue;
      const double w = f.W(c), u = f.U(c);
      if (w > 0.3 || w < -kOpeningReach || u < 0.0 || u > f.length) continue;
      const double v = std::clamp(c.z(), f.vmin + 0.05, f.vmax - 0.05);
      Hole h{fi, 0, 0, 0, 0, std::abs(w)};
      // The element's own extent along the face bounds the hole (an opening at an open edge).
      double eu0 = 1e300, eu1 = -1e300;
      for (int k = 0; k < 8; ++k) {
        const Vector3d corner = e.box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k));
        eu0 = std::min(eu0, f.U(corner));
        eu1 = std::max(eu1, f.U(corner));
      }
      if (!GapAround(Coverage(f, false, v), u, std::max(0.0, eu0 - 0.1),
                     std::min(f.length, eu1 + 0.1), &h.u0, &h.u1))
        continue;
      if (!GapAround(Coverage(f, true, 0.5 * (h.u0 + h.u1)), v, f.vmin, f.vmax, &h.v0, &h.v1))
        continue;
      if (h.u1 - h.u0 < 0.05 || h.v1 - h.v0 < 0.05) continue;
      holes.push_back(h);
    }
    std::stable_sort(holes.begin(), holes.end(),
                     [](const Hole& a, const Hole& b) { return a.dist < b.dist; });
    return holes;
  }

  const StructuralElement& WallOf(const Face& f) const {
    for (const auto& w : walls_)
      if (w.id == f.id) return w;
    throw std::logic_error("face without wall");
  }

  void FillRect(Opening* o, const Hole& h) const {
    const Face& f = faces_[h.face];
    const StructuralElement& w = WallOf(f);
    o->u0 = h.u0 - f.umin;
    o->u1 = h.u1 - f.umin;
    o->v0 = h.v0 - w.origin.z();
    o->v1 = h.v1 - w.origin.z();
    auto P = [&](double u, double v) {
      return Vector3d(w.origin + u * w.u_axis + Vector3d(0, 0, v));
    };
    o->corners = {P(o->u0, o->v0), P(o->u0, o->v1), P(o->u1, o->v1), P(o->u1, o->v0)};
  }

  double DoorAngleDeg(const std::string& id, const Element& e) const {
    for (const std::string& key :
         {id, NodeGuid(e.node), NodeLabel(e.node), e.node, NiceNameOnly(e.node)}) {
      const auto it = p_.door_angles_deg.find(key);
      if (!key.empty() && it != p_.door_angles_deg.end()) {
        used_door_keys_.insert(it->first);
        return it->second;
      }
    }
    return p_.door_angle_deg;
  }

  std::string NiceNameOnly(const std::string& node) const {
    const auto it = names_.find(NodeGuid(node));
    return it != names_.end() ? it->second : "";
  }

  int LeafMaterial() {
    for (std::size_t i = 0; i < scene_.materials.size(); ++i)
      if (scene_.materials[i].name == "door_leaf") return static_cast<int>(i);
    Material m;
    m.name = "door_leaf";
    m.base_color = Eigen::Vector4f(0.55f, 0.40f, 0.25f, 1.0f);
    scene_.materials.push_back(m);
    return static_cast<int>(scene_.materials.size()) - 1;
  }

  void Openings() {
    int doors = 0, windows = 0;
    for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
      const Element& e = elements_[ei];
      if (!e.in_storey || (e.role != Role::kDoor && e.role != Role::kWindow)) continue;
      const bool door = e.role == Role::kDoor;
      std::vector<Hole> holes = HolesAround(e);
      if (holes.empty()) {
        for (std::size_t pi : e.parts) AllToLeftover(ei, pi);
        out_.report.push_back(NiceName(e.node) +
                              ": no hole in a room wall of this storey "
                              "around it; kept as other");
        continue;
      }
      {
        // The format's openings are rectangles: say so when the hole is not one (round window).
        const Hole& h = holes[0];
        const Face& f = faces_[h.face];
        const std::vector<HalfSpace> rect{{-f.dir, -f.dir.dot(f.a) - h.u0},
                                          {f.dir, f.dir.dot(f.a) + h.u1},
                                          {-Vector3d::UnitZ(), -h.v0},
                                          {Vector3d::UnitZ(), h.v1}};
        double covered = 0.0;
        for (const auto& [el, piece] : f.pieces) {
          Poly3 in;
          std::vector<Poly3> outside;
          Split(piece, rect, &in, &outside);
          covered += Area(in);
        }
        // An element that fills only part of its hole leaves the rest open (a window in an
        // opening cut down to the floor).
        if (e.box.min().z() > h.v0 + 0.05 || e.box.max().z() < h.v1 - 0.05)
          out_.report.push_back(NiceName(e.node) + ": fills z " + Fmt(e.box.min().z(), 2) + " to " +
                                Fmt(e.box.max().z(), 2) + " m of its hole's " + Fmt(h.v0, 2) +
                                " to " + Fmt(h.v1, 2) + " m; the rest of the hole is open");
        const double share = covered / ((h.u1 - h.u0) * (h.v1 - h.v0));
        if (share > 0.001)
          out_.report.push_back(NiceName(e.node) + ": its hole is not a rectangle (" +
                                Fmt(100.0 * share, 1) +
                                " % of its bounding rectangle is wall); "
                                "the truth keeps the rectangle and validate will say so");
      }
      Opening o;
      o.id = door ? "D" + std::to_string(++doors) : "W" + std::to_string(++windows);
      o.type = door ? OpeningType::kDoor : OpeningType::kWindow;
      const Face& f0 = faces_[holes[0].face];
      const RoomData& r0 = rooms_[f0.room];
      o.host_walls = {f0.id};
      o.rooms = {r0.room.id};
      FillRect(&o, holes[0]);
      for (const Hole& h : holes) holes_.push_back(h);
      std::string room_b;
      std::size_t hole_b = holes.size();
      if (door)
        for (std::size_t k = 1; k < holes.size(); ++k) {
          const Face& fk = faces_[holes[k].face];
          if (fk.n.dot(f0.n) < -kFacingCos && fk.room != f0.room) {
            o.host_walls.push_back(fk.id);
            room_b = rooms_[fk.room].room.id;
            o.rooms.push_back(room_b);
            hole_b = k;
            break;
          }
        }
      if (!door) {
        o.sill_height = o.v0 + (WallOf(f0).origin.z() - r0.room.floor_z);
        for (std::size_t pi : e.parts) {
          const MeshPart& part = scene_.parts[pi];
          const bool glass = part.material >= 0 && scene_.materials[part.material].transmission > 0;
          Bucket& b =
              out_bucket_.Get(o.id, glass ? ElementClass::kWindowGlass : ElementClass::kWindowFrame,
                              "window", r0.room.id, part.material);
          for (const auto& t : part.triangles)
            b.pieces.push_back({part.positions[t[0]].cast<double>(),
                                part.positions[t[1]].cast<double>(),
                                part.positions[t[2]].cast<double>()});
        }
        out_.report.push_back("window " + o.id + " = " + NiceName(e.node) + " in " + f0.id + ", " +
                              Fmt(o.u1 - o.u0, 2) + " x " + Fmt(o.v1 - o.v0, 2) + " m");
        out_.truth.openings.push_back(o);
        continue;
      }
      // Door: the BIM leaf and frame are replaced by a leaf hinged at a jamb of the hole
      // (docs/scene-import.md). Where it swings: the first of (larger room, smaller room) x
      // (left, right hinge) whose swept square fits in that room; else the nearest room, left.
      const double deg = DoorAngleDeg(o.id, e);
      const double lambda = DegToRad(deg);
      const double lt = p_.leaf_thickness;
      std::vector<std::size_t> sides{0};
      if (hole_b < holes.size()) {
        sides.push_back(hole_b);
        if (SignedArea(rooms_[faces_[holes[hole_b].face].room].poly) > SignedArea(r0.poly))
          std::swap(sides[0], sides[1]);
      }
      struct Swing {
        const Face* f;
        const Hole* h;
        bool left;
        Vector3d n, dd, hinge;
        double lw;
      };
      auto make = [&](std::size_t k, bool left) {
        const Hole& h = holes[k];
        const Face& f = faces_[h.face];
        Swing sw{&f, &h, left, f.n, Vector3d::Zero(), Vector3d::Zero(), 0.0};
        // Left hinge seen from the swing room: hinge -> latch = z x n = -dir, hinge at u1.
        sw.dd =
            left ? Vector3d(Vector3d::UnitZ().cross(f.n)) : Vector3d(f.n.cross(Vector3d::UnitZ()));
        const double u_h = left ? h.u1 - kLeafGap : h.u0 + kLeafGap;
        sw.hinge = f.a + u_h * f.dir + 0.001 * f.n + Vector3d(0, 0, h.v0 - f.a.z());
        sw.lw = h.u1 - h.u0 - 2 * kLeafGap;
        return sw;
      };
      auto fits = [&](const Swing& sw) {
        const Polygon2& poly = rooms_[sw.f->room].poly;
        for (const auto& [a, b] : {std::pair{0.02, 1.0}, std::pair{1.0, 1.0}, std::pair{0.5, 0.5}})
          if (!PointInPolygon((sw.hinge + sw.lw * (a * sw.dd + b * sw.n)).head<2>(), poly))
            return false;
        return true;
      };
      Swing sw = make(0, true);
      bool fitted = false;
      for (std::size_t k : sides) {
        for (bool left : {true, false}) {
          const Swing c = make(k, left);
          if (fits(c)) {
            sw = c;
            fitted = true;
            break;
          }
        }
        if (fitted) break;
      }
      if (!fitted)
        out_.report.push_back(NiceName(e.node) +
                              ": its leaf fits in neither room when open; "
                              "it swings into " +
                              r0.room.id);
      const Vector3d n = sw.n, dd = sw.dd;
      const Vector3d axis = dd.cross(n).normalized();
      const Vector3d rd = std::cos(lambda) * dd + std::sin(lambda) * n;
      const Vector3d rn = std::cos(lambda) * n - std::sin(lambda) * dd;
      const std::string swing_room = rooms_[sw.f->room].room.id;
      Bucket& leaf = out_bucket_.Get(o.id, ElementClass::kDoorLeaf, "door", swing_room,
                                     LeafMaterial(), o.id + "/leaf");
      MeshPart box;
      PartBuilder pb(&box);
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      // A left hinge makes (rd, rn, z) left-handed (rd x rn = dd x n = -z): mirror x then.
      const bool mirror = rd.cross(rn).z() < 0.0;
      X.linear().col(0) = mirror ? Vector3d(-rd) : rd;
      X.linear().col(1) = rn;
      X.linear().col(2) = Vector3d::UnitZ();
      X.translation() = sw.hinge;
      const double top = sw.h->v1 - sw.h->v0 - kLeafGap;
      if (mirror)
        pb.AddBox(X, {-sw.lw, -lt, 0.01}, {0.0, 0.0, top});
      else
        pb.AddBox(X, {0.0, -lt, 0.01}, {sw.lw, 0.0, top});
      for (const auto& t : box.triangles)
        leaf.pieces.push_back({box.positions[t[0]].cast<double>(),
                               box.positions[t[1]].cast<double>(),
                               box.positions[t[2]].cast<double>()});
      o.hinge_side = sw.left ? "left" : "right";
      o.swing_room = swing_room;
      o.hinge_point = sw.hinge;
      o.hinge_axis = axis;
      o.opening_angle = lambda;
      o.state = DoorStateFromAngle(lambda);
      o.leaf_thickness = lt;
      out_.truth.openings.push_back(o);
      out_.truth.connections.push_back({o.id, r0.room.id, room_b});
      out_.report.push_back("door " + o.id + " = " + NiceName(e.node) + " between " + r0.room.id +
                            " and " + (room_b.empty() ? "outside" : room_b) + ", " +
                            Fmt(o.u1 - o.u0, 2) + " x " + Fmt(o.v1 - o.v0, 2) + " m, at " +
                            Fmt(deg, 1) + " deg, hinged " + o.hinge_side + " into " + swing_room +
                            " (BIM leaf replaced)");
    }
  }

  // Rooms sharing a boundary stretch without a wall (open-plan spaces): open passages.
  void Passages() {
    std::set<std::pair<int, int>> done;
    for (std::size_t fi = 0; fi < faces_.size(); ++fi)
      for (std::size_t gi = fi + 1; gi < faces_.size(); ++gi) {
        const Face& f = faces_[fi];
        const Face& g = faces_[gi];
        if (f.room == g.room || f.n.dot(g.n) > -kFacingCos ||
            std::abs(f.W(g.a)) > kPassageTolerance || done.count({f.room, g.room}))
          continue;
        const double g0 = f.U(g.a), g1 = f.U(g.a + g.length * g.dir);
        const double s0 = std::max(0.0, std::min(g0, g1)),
                     s1 = std::min(f.length, std::max(g0, g1));
        if (s1 - s0 < kMinClearDoorWidth) continue;
        const double v = f.z0 + 0.5 * (std::min(f.z1, g.z1) - f.z0);
        std::vector<std::pair<double, double>> cov = Coverage(f, false, v);
        for (const Hole& h : holes_)
          if (h.face == fi) cov.emplace_back(h.u0, h.u1);  // doors and windows are not passages
        std::sort(cov.begin(), cov.end());
        double widest = 0.0, at = s0;
        for (const auto& [a, b] : cov) {
          if (b <= at) continue;
          widest = std::max(widest, std::min(a, s1) - at);
          at = std::max(at, b);
          if (at >= s1) break;
        }
        widest = std::max(widest, s1 - at);
        if (widest < kMinClearDoorWidth) continue;
        done.insert({f.room, g.room});
        done.insert({g.room, f.room});
        out_.truth.connections.push_back({"", rooms_[f.room].room.id, rooms_[g.room].room.id});
        out_.truth.format_version = kTruthFormatVersionPassages;
        out_.report.push_back("open passage between " + rooms_[f.room].room.id + " and " +
                              rooms_[g.room].room.id + ": " + Fmt(widest, 2) +
                              " m of shared boundary without a wall");
      }
  }

  void Components() {
    int furniture = 0;
    std::map<std::string, int> counts;
    for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
      const Element& e = elements_[ei];
      if (!e.in_storey) continue;
      if (e.role == Role::kFurniture) {
        FurnitureItem fi;
        fi.id = "furniture_" + std::to_string(++furniture);
        fi.type = e.ifc;
        const int r = RoomAt(e.box.center());
        fi.room = r >= 0 ? rooms_[r].room.id : "";
        Yawed(e, &fi);
        for (std::size_t pi : e.parts) {
          const MeshPart& part = scene_.parts[pi];
          Bucket& b =
              out_bucket_.Get(fi.id, ElementClass::kFurniture, fi.type, fi.room, part.material);
          for (const auto& t : part.triangles)
            b.pieces.push_back({part.positions[t[0]].cast<double>(),
                                part.positions[t[1]].cast<double>(),
                                part.positions[t[2]].cast<double>()});
        }
        out_.truth.furniture.push_back(fi);
        continue;
      }
      if (e.role != Role::kComponent) continue;
      const Vector3d size = e.box.sizes();
      if (Lower(e.ifc) == "ifcbuildingelementproxy" && size.maxCoeff() > 1.5) {
        for (std::size_t pi : e.parts) AllToLeftover(ei, pi);
        continue;  // a large proxy is not a component
      }
      if (!HostComponent(ei, &counts)) {
        for (std::size_t pi : e.parts) AllToLeftover(ei, pi);
        out_.report.push_back(NiceName(e.node) + ": no wall face or ceiling within " +
                              Fmt(p_.component_snap * 100, 1) + " cm; kept as other");
      }
    }
  }

  // Smallest-area yaw of the element's plan extent, from its horizontal edge directions.
  void Yawed(const Element& e, FurnitureItem* fi) const {
    std::vector<Vector3d> pts;
    std::set<long long> yaws{0};
    for (std::size_t pi : e.parts) {
      const MeshPart& part = scene_.parts[pi];
      for (const auto& v : part.positions) pts.push_back(v.cast<double>());
      for (const auto& t : part.triangles)
        for (int k = 0; k < 3; ++k) {
          const Vector3d d = (part.positions[t[(k + 1) % 3]] - part.positions[t[k]]).cast<double>();
          if (std::hypot(d.x(), d.y()) < 0.05) continue;
          double a = std::atan2(d.y(), d.x());
          a = std::fmod(a + 4 * kPi, kPi / 2);
          yaws.insert(std::llround(RadToDeg(a) * 10) % 900);
        }
    }
    double best = 1e300;
    for (long long y10 : yaws) {
      const double yaw = DegToRad(double(y10) / 10.0);
      const Vector2d ex(std::cos(yaw), std::sin(yaw)), ey(-std::sin(yaw), std::cos(yaw));
      Eigen::AlignedBox3d b;
      for (const auto& p : pts) b.extend(Vector3d(ex.dot(p.head<2>()), ey.dot(p.head<2>()), p.z()));
      const double area = b.sizes().x() * b.sizes().y();
      if (area < best - 1e-9) {
        best = area;
        fi->yaw = yaw;
        fi->size = b.sizes();
        const Vector3d c = b.center();
        fi->centre =
            Vector3d(ex.x() * c.x() + ey.x() * c.y(), ex.y() * c.x() + ey.y() * c.y(), c.z());
      }
    }
  }

  bool HostComponent(std::size_t ei, std::map<std::string, int>* counts) {
    const Element& e = elements_[ei];
    std::vector<Vector3d> pts;
    for (std::size_t pi : e.parts)
      for (const auto& v : scene_.parts[pi].positions) pts.push_back(v.cast<double>());
    // Nearest wall face whose plane the component's back is within the snap distance of.
    double best = 1e300;
    const StructuralElement* host = nullptr;
    double gap = 0.0;
    for (const StructuralElement& w : walls_) {
      double dmin = 1e300;
      Eigen::AlignedBox2d fp;
      for (const auto& p : pts) {
        dmin = std::min(dmin, (p - w.origin).dot(w.normal));
        fp.extend(Vector2d((p - w.origin).dot(w.u_axis), p.z() - w.origin.z()));
      }
      if (std::abs(dmin) > p_.component_snap || fp.min().x() < -1e-3 ||
          fp.max().x() > w.length + 1e-3 || fp.min().y() < -1e-3 || fp.max().y() > w.height + 1e-3)
        continue;
      if (std::abs(dmin) < best) {
        best = std::abs(dmin);
        host = &w;
        gap = dmin;
      }
    }
    bool ceiling = false;
    for (std::size_t r = 0; r < rooms_.size(); ++r) {
      double top = -1e300;
      bool inside = true;
      for (const auto& p : pts) {
        top = std::max(top, p.z());
        inside = inside && PointInPolygon(p.head<2>(), rooms_[r].poly);
      }
      const double d = rooms_[r].room.ceiling_z - top;
      if (inside && std::abs(d) <= p_.component_snap && std::abs(d) < best) {
        best = std::abs(d);
        host = &ceilings_[r];
        gap = d;
        ceiling = true;
      }
    }
    if (host == nullptr) return false;
    const Vector3d shift = ceiling ? Vector3d(0, 0, gap) : Vector3d(-gap * host->normal);
    ServiceComponent s;
    const auto type = type_class_.find(NodeGuid(e.node));
    std::string cls =
        ComponentClass(e.ifc, type == type_class_.end() ? "" : type->second, e.box.sizes());
    if (cls == "smoke_detector" && !ceiling) cls = "other:" + e.ifc;
    s.bsc_class = cls;
    s.id = (cls.rfind("other:", 0) == 0 ? "other" : cls) + "_" + std::to_string(++(*counts)[cls]);
    s.host = host->id;
    s.room = host->rooms.empty() ? "" : host->rooms[0];
    for (std::size_t pi : e.parts) {
      const MeshPart& part = scene_.parts[pi];
      Bucket& b =
          out_bucket_.Get(s.id, ElementClass::kServiceComponent, cls, s.room, part.material);
      for (const auto& t : part.triangles)
        b.pieces.push_back({part.positions[t[0]].cast<double>() + shift,
                            part.positions[t[1]].cast<double>() + shift,
                            part.positions[t[2]].cast<double>() + shift});
    }
    if (ceiling) {
      Eigen::AlignedBox3d b;
      for (const auto& p : pts) b.extend(p + shift);
      s.centre = Vector3d(b.center().x(), b.center().y(), host->polygons[0][0].z());
      s.normal = -Vector3d::UnitZ();
      s.size = Vector3d(b.sizes().x(), b.sizes().y(), b.sizes().z());
    } else {
      Eigen::AlignedBox2d fp;
      double depth = 0.0;
      for (const auto& p : pts) {
        const Vector3d q = p + shift;
        fp.extend(Vector2d((q - host->origin).dot(host->u_axis), q.z() - host->origin.z()));
        depth = std::max(depth, (q - host->origin).dot(host->normal));
      }
      s.centre = host->origin + fp.center().x() * host->u_axis + Vector3d(0, 0, fp.center().y());
      s.normal = host->normal;
      s.size = Vector3d(fp.sizes().x(), fp.sizes().y(), depth);
    }
    out_.truth.service_components.push_back(s);
    if (std::abs(gap) > 1e-3)
      out_.report.push_back(NiceName(e.node) + ": " + Fmt(std::abs(gap) * 1000, 1) + " mm off " +
                            host->id + "; moved onto it");
    out_.report.push_back("component " + s.id + " = " + NiceName(e.node) + " (" + cls + ") on " +
                          host->id);
    return true;
  }

  void Finish() {
    for (const auto& [key, deg] : p_.door_angles_deg)
      if (!used_door_keys_.count(key))
        throw InputError(path_, "--doors names no door of this storey", "'" + key + "'",
                         "a door id (D1), IFC GlobalId or IFC Name");
    out_.truth.scene_name = CleanUtf8(std::filesystem::path(path_).stem().string());
    for (const RoomData& r : rooms_) out_.truth.rooms.push_back(r.room);
    for (const auto& w : walls_) out_.truth.elements.push_back(w);
    for (const auto& f : floors_) out_.truth.elements.push_back(f);
    for (const auto& c : ceilings_) out_.truth.elements.push_back(c);
    for (const auto& c : columns_) out_.truth.elements.push_back(c);
    std::set<std::string> emitted;
    for (const Bucket& b : out_bucket_.buckets()) {
      if (b.cls != ElementClass::kOther || b.pieces.empty() || !emitted.insert(b.id).second)
        continue;
      StructuralElement s;
      s.id = b.id;
      s.element_class = ElementClass::kOther;
      out_.truth.elements.push_back(s);
    }
    for (std::size_t i = 0; i < elements_.size(); ++i) {
      bool contained = false;
      for (std::size_t pi : elements_[i].parts) contained = contained || storey_parts_.count(pi);
      if (contained && !elements_[i].merged) ++out_.storey_elements[elements_[i].ifc];
    }
    out_.walls_with_room_faces = static_cast<int>(walls_with_faces_.size());
    std::string counts;
    for (const auto& [cls, n] : out_.storey_elements)
      counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + cls;
    out_.report.push_back("IFC elements with geometry on the storey: " + counts);
    out_.report.push_back(std::to_string(out_.walls_with_room_faces) +
                          " IFC wall(s) give the room-side wall faces");
    out_.scene.source = path_;
    // Only the materials (and their textures) the parts use, in order of first use.
    out_.scene.parts = out_bucket_.Parts();
    std::map<int, int> material_index, texture_index;
    for (MeshPart& part : out_.scene.parts) {
      if (part.material < 0) continue;
      auto [it, fresh] =
          material_index.emplace(part.material, static_cast<int>(out_.scene.materials.size()));
      if (fresh) {
        Material m = scene_.materials[static_cast<std::size_t>(part.material)];
        // The format's materials are all double-sided; BIM solids' winding varies.
        m.double_sided = true;
        if (m.base_color_texture >= 0) {
          auto [t, new_texture] = texture_index.emplace(
              m.base_color_texture, static_cast<int>(out_.scene.textures.size()));
          if (new_texture)
            out_.scene.textures.push_back(
                scene_.textures[static_cast<std::size_t>(m.base_color_texture)]);
          m.base_color_texture = t->second;
        }
        out_.scene.materials.push_back(m);
      }
      part.material = it->second;
    }
    // Sort opening-less other ids to keep the truth's element order stable (file order).
    std::set<std::string> ids;
    for (const auto& e : out_.truth.elements)
      if (!ids.insert(e.id).second)
        throw InputError(path_, "two elements have the same id", "'" + e.id + "'",
                         "unique IFC GlobalIds");
  }

  const std::string path_;
  const BimImportParams p_;
  Scene scene_;
  std::map<std::string, std::string> names_;       // GlobalId -> IFC Name
  std::map<std::string, std::string> type_class_;  // GlobalId -> "ifcoutlet" (its type object)
  std::map<std::string, std::vector<std::string>> storey_spaces_;  // storey -> space GlobalIds
  // storey GlobalId -> (element GlobalId, ENTITY) of IfcRelContainedInSpatialStructure
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> storey_contained_;
  std::set<std::size_t> merged_parts_, storey_parts_;
  std::vector<Element> elements_;
  std::string storey_;
  double next_storey_low_ = 1e300;
  double z0_ = 0.0, top_ = -1e300;
  std::vector<RoomData> rooms_;
  std::vector<Face> faces_;
  std::vector<Hole> holes_;                 // of every opening, on every face it was found in
  std::set<std::size_t> walls_with_faces_;  // elements
  std::map<std::size_t, double> floor_area_, ceiling_area_;
  std::map<int, int> columns_in_;
  std::vector<StructuralElement> walls_, floors_, ceilings_, columns_;
  std::set<std::string> other_ids_;
  mutable std::set<std::string> used_door_keys_;
  Output out_bucket_;
  BimImport out_;
};

}  // namespace

void BimImportParams::Validate() const {
  auto range = [](const std::string& field, double v, double lo, double hi, bool open_lo) {
    if (!std::isfinite(v) || v > hi || (open_lo ? v <= lo : v < lo))
      throw InputError("", "import parameter " + field + " out of range", Fmt(v, 4),
                       std::string(open_lo ? "(" : "[") + Fmt(lo, 3) + ", " + Fmt(hi, 3) + "]");
  };
  range("door_angle_deg", door_angle_deg, 0.0, 180.0, false);
  for (const auto& [id, deg] : door_angles_deg) range("doors " + id, deg, 0.0, 180.0, false);
  range("leaf_thickness", leaf_thickness, 0.0, 0.2, true);
  range("plane_tolerance", plane_tolerance, 0.0, 0.05, true);
  range("component_snap", component_snap, 0.0, 0.5, false);
  range("min_face_area", min_face_area, 0.0, 1e3, true);
}

std::map<std::string, double> ParseDoorAngles(const std::vector<std::string>& items) {
  std::map<std::string, double> out;
  for (const std::string& item : items) {
    const std::size_t eq = item.rfind('=');
    char* end = nullptr;
    const std::string num = eq == std::string::npos ? "" : item.substr(eq + 1);
    const double deg = std::strtod(num.c_str(), &end);
    if (eq == std::string::npos || eq == 0 || num.empty() || *end != '\0' || !std::isfinite(deg) ||
        deg < 0.0 || deg > 180.0)
      throw InputError("--doors", "malformed door angle", "'" + item + "'",
                       "ID=DEG with DEG in [0, 180]");
    if (!out.emplace(item.substr(0, eq), deg).second)
      throw InputError("--doors", "door given twice", "'" + item.substr(0, eq) + "'", "once");
  }
  return out;
}

BimImport ImportBim(const std::string& path, const BimImportParams& params) {
  return Importer(path, params).Run();
}

void WriteBimImport(const BimImport& imported, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create directory", ec.message());
  const std::filesystem::path d(dir);
  WriteGlb(imported.scene, (d / "scene.glb").string());
  WriteGroundTruth(imported.truth, (d / "scene.truth.json").string());
}

std::vector<BimStorey> ListIfcStoreys(const std::string& path) {
  const std::string text = ReadText(path);
  const std::string schema = IfcSchemaOf(text);
  if (schema.rfind("IFC2X", 0) != 0)
    throw InputError(path, "unsupported IFC schema (assimp 5.2.5 reads IFC 2x3 only)",
                     schema.empty() ? "no FILE_SCHEMA" : schema, "IFC2X3");
  const StepIndex index = IndexStep(text);
  const double scale = FullLengthScale(text, index, path);
  std::vector<BimStorey> out;
  for (const auto& [id, body] : index.bodies) {
    if (EntityOf(body) != "IFCBUILDINGSTOREY") continue;
    const std::vector<std::string> a = Attributes(body);
    BimStorey s;
    if (!a.empty()) s.global_id = StepString(a[0]);
    if (a.size() > 2) s.name = StepString(a[2]);
    if (a.size() > 9 && a[9] != "$") {
      char* end = nullptr;
      const double v = std::strtod(a[9].c_str(), &end);
      if (end != a[9].c_str() && std::isfinite(v)) {
        s.elevation = v * scale;
        s.has_elevation = true;
      }
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace mopad::scenes
