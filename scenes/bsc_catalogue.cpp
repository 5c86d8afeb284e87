#include "scenes/bsc_catalogue.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/polygon.h"
#include "common/srgb.h"

// Building service components (the paper's §3.4, Table 3). Every class is built from a few
// convex prisms (boxes, polygonal cylinders, a triangular plate) in its local frame:
//   x = width axis, y = up (ceiling: world y), z = out of the host surface, back face at z = 0,
//   centred on x = y = 0.
// Its colour texture is drawn procedurally in the same metric (x, y) frame and mapped onto every
// front-facing triangle by a planar projection along z, so the orthographic front view of the
// model shows exactly the pictogram. Dimensions are those of common European products
// (Schuko sockets in 80 mm frames, ISO 7010 signs 200 mm, EN 54-11 manual call points, ...).

namespace mopad::scenes {
namespace {

using interfaces::Mounting;

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Colours: sRGB bytes (what the pictograms are drawn in); materials take them to linear.

struct Rgb {
  std::uint8_t r, g, b;
};

constexpr Rgb kWhite{245, 245, 242};      // RAL 9016 traffic white (plastics, plates)
constexpr Rgb kPureWhite{252, 252, 252};  // pictogram symbols
constexpr Rgb kPanelGrey{203, 208, 204};  // RAL 7035 light grey (enclosures)
constexpr Rgb kDarkGrey{70, 72, 75};      // brackets, door gaps
constexpr Rgb kBlack{25, 25, 25};
constexpr Rgb kHole{35, 35, 38};            // socket contact holes
constexpr Rgb kCupGrey{214, 214, 210};      // socket cup
constexpr Rgb kClipGrey{165, 165, 160};     // earthing clips
constexpr Rgb kSignalRed{200, 30, 32};      // RAL 3001 (ISO 7010 fire signs, extinguishers)
constexpr Rgb kSafetyGreen{0, 135, 80};     // RAL 6032 (escape route signs)
constexpr Rgb kWarningYellow{250, 200, 0};  // RAL 1003 (ISO 7010 W012)
constexpr Rgb kTextGrey{55, 58, 66};

Eigen::Vector4f LinearColour(Rgb c) {
  return {static_cast<float>(SrgbToLinear(c.r / 255.0)),
          static_cast<float>(SrgbToLinear(c.g / 255.0)),
          static_cast<float>(SrgbToLinear(c.b / 255.0)), 1.0f};
}

// ---------------------------------------------------------------------------------------------
// Canvas: a texture addressed in the model's metric (x, y) frame, y up, origin at the centre.
// Shapes are inside-predicates; each pixel is covered by 4x4 sub-samples for smooth edges.

using P2 = Eigen::Vector2d;

class Canvas {
 public:
  Canvas(double width, double height, Rgb background) : width_(width), height_(height) {
    // ~1 mm per texel, at most 256 texels along the longer side, at least 16 along any side.
    const double scale = std::min(1000.0, 256.0 / std::max(width, height));
    px_w_ = std::max(16, static_cast<int>(std::lround(width * scale)));
    px_h_ = std::max(16, static_cast<int>(std::lround(height * scale)));
    rgb_.assign(static_cast<std::size_t>(px_w_) * px_h_ * 3, 0);
    for (int i = 0; i < px_w_ * px_h_; ++i) {
      rgb_[3 * i + 0] = background.r;
      rgb_[3 * i + 1] = background.g;
      rgb_[3 * i + 2] = background.b;
    }
  }

  /// Blends `c` over every pixel with the coverage of `inside` within [x0,x1]x[y0,y1].
  void Fill(double x0, double y0, double x1, double y1, Rgb c,
            const std::function<bool(double, double)>& inside) {
    const double dx = width_ / px_w_, dy = height_ / px_h_;
    const int i0 = std::max(0, static_cast<int>(std::floor((x0 + width_ / 2) / dx)));
    const int i1 = std::min(px_w_ - 1, static_cast<int>(std::floor((x1 + width_ / 2) / dx)));
    const int j0 = std::max(0, static_cast<int>(std::floor((height_ / 2 - y1) / dy)));
    const int j1 = std::min(px_h_ - 1, static_cast<int>(std::floor((height_ / 2 - y0) / dy)));
    constexpr int kSub = 4;
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        int hits = 0;
        for (int sj = 0; sj < kSub; ++sj) {
          for (int si = 0; si < kSub; ++si) {
            const double x = -width_ / 2 + (i + (si + 0.5) / kSub) * dx;
            const double y = height_ / 2 - (j + (sj + 0.5) / kSub) * dy;
            if (inside(x, y)) ++hits;
          }
        }
        if (hits == 0) continue;
        const double a = static_cast<double>(hits) / (kSub * kSub);
        std::uint8_t* p = &rgb_[3 * (static_cast<std::size_t>(j) * px_w_ + i)];
        const std::array<std::uint8_t, 3> src{c.r, c.g, c.b};
        for (int k = 0; k < 3; ++k) {
          p[k] = static_cast<std::uint8_t>(std::lround((1.0 - a) * p[k] + a * src[k]));
        }
      }
    }
  }

  void Rect(double cx, double cy, double w, double h, Rgb c) {
    const double x0 = cx - w / 2, x1 = cx + w / 2, y0 = cy - h / 2, y1 = cy + h / 2;
    Fill(x0, y0, x1, y1, c,
         [=](double x, double y) { return x >= x0 && x <= x1 && y >= y0 && y <= y1; });
  }
  /// Rectangle outline of line thickness `t`, drawn inside the w x h box.
  void RectOutline(double cx, double cy, double w, double h, double t, Rgb c) {
    const double x0 = cx - w / 2, x1 = cx + w / 2, y0 = cy - h / 2, y1 = cy + h / 2;
    Fill(x0, y0, x1, y1, c, [=](double x, double y) {
      const bool in = x >= x0 && x <= x1 && y >= y0 && y <= y1;
      const bool inner = x > x0 + t && x < x1 - t && y > y0 + t && y < y1 - t;
      return in && !inner;
    });
  }
  void Circle(double cx, double cy, double r, Rgb c) {
    Fill(cx - r, cy - r, cx + r, cy + r, c,
         [=](double x, double y) { return (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r; });
  }
  void Ring(double cx, double cy, double r_in, double r_out, Rgb c) {
    Fill(cx - r_out, cy - r_out, cx + r_out, cy + r_out, c, [=](double x, double y) {
      const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
      return d2 <= r_out * r_out && d2 >= r_in * r_in;
    });
  }
  /// Simple polygon (any winding, even-odd rule).
  void Polygon(const std::vector<P2>& pts, Rgb c) {
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (const P2& p : pts) {
      x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x());
      y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
    }
    Fill(x0, y0, x1, y1, c, [&pts](double x, double y) { return PointInPolygon(P2(x, y), pts); });
  }
  /// Thick line segment with round caps.
  void Line(P2 a, P2 b, double thickness, Rgb c) {
    const double r = thickness / 2;
    Fill(std::min(a.x(), b.x()) - r, std::min(a.y(), b.y()) - r, std::max(a.x(), b.x()) + r,
         std::max(a.y(), b.y()) + r, c,
         [=](double x, double y) { return SquaredDistanceToSegment(P2(x, y), a, b) <= r * r; });
  }
  void Polyline(const std::vector<P2>& pts, double thickness, Rgb c) {
    for (std::size_t i = 1; i < pts.size(); ++i) Line(pts[i - 1], pts[i], thickness, c);
  }

  Texture ToTexture(const std::string& name) const {
    Texture t;
    t.name = name;
    t.width = px_w_;
    t.height = px_h_;
    t.repeat = false;
    t.rgba.resize(static_cast<std::size_t>(px_w_) * px_h_ * 4);
    for (int i = 0; i < px_w_ * px_h_; ++i) {
      t.rgba[4 * i + 0] = rgb_[3 * i + 0];
      t.rgba[4 * i + 1] = rgb_[3 * i + 1];
      t.rgba[4 * i + 2] = rgb_[3 * i + 2];
      t.rgba[4 * i + 3] = 255;
    }
    return t;
  }

 private:
  double width_, height_;
  int px_w_ = 0, px_h_ = 0;
  std::vector<std::uint8_t> rgb_;
};

// Transforms a shape given in a unit frame ([-1, 1]^2) to centre c and half-size s.
std::vector<P2> Place(const std::vector<P2>& unit, P2 c, double s) {
  std::vector<P2> out;
  out.reserve(unit.size());
  for (const P2& p : unit) out.push_back(c + s * p);
  return out;
}

// ---- pictogram elements (unit frame, y up) ----

const std::vector<P2>& UnitBolt() {
  static const std::vector<P2> k = {{-0.10, 1.00},  {0.45, 1.00},   {0.12, 0.18},  {0.50, 0.18},
                                    {-0.30, -1.00}, {-0.05, -0.08}, {-0.42, -0.08}};
  return k;
}

const std::vector<P2>& UnitFlame() {
  static const std::vector<P2> k = {{-0.55, -0.45}, {-0.62, -0.05}, {-0.45, 0.35}, {-0.30, 0.10},
                                    {-0.18, 0.55},  {0.00, 1.00},   {0.12, 0.50},  {0.32, 0.75},
                                    {0.38, 0.25},   {0.55, 0.45},   {0.62, 0.00},  {0.55, -0.45},
                                    {0.30, -0.75},  {0.00, -0.82},  {-0.30, -0.75}};
  return k;
}

// Equilateral warning triangle (ISO 7010 W012): black border, yellow field, black bolt.
void WarningTriangle(Canvas& cv, P2 centre, double side) {
  const double h = side * std::sqrt(3.0) / 2;
  auto tri = [&](double s) {
    const double hh = s * std::sqrt(3.0) / 2;
    // centroid-based shrink keeps the border width uniform
    const P2 g = centre + P2(0, -h / 2 + h / 3);
    return std::vector<P2>{g + P2(-s / 2, -hh / 3), g + P2(s / 2, -hh / 3), g + P2(0, 2 * hh / 3)};
  };
  cv.Polygon(tri(side), kBlack);
  cv.Polygon(tri(side * 0.78), kWarningYellow);
  const P2 g = centre + P2(0, -h / 2 + h / 3);
  cv.Polygon(Place(UnitBolt(), g + P2(0, -0.02 * side), 0.22 * side), kBlack);
}

// Running figure (ISO 7010 E001/E002), about 2s tall, facing +x.
void RunningFigure(Canvas& cv, P2 c, double s, Rgb col) {
  const double t = 0.22 * s;
  cv.Circle(c.x() + 0.18 * s, c.y() + 0.78 * s, 0.17 * s, col);
  cv.Line(c + P2(0.10 * s, 0.52 * s), c + P2(-0.12 * s, 0.0), 1.25 * t, col);  // torso
  cv.Polyline({c + P2(0.06 * s, 0.45 * s), c + P2(0.35 * s, 0.30 * s), c + P2(0.55 * s, 0.45 * s)},
              t, col);  // front arm
  cv.Polyline(
      {c + P2(0.04 * s, 0.45 * s), c + P2(-0.25 * s, 0.38 * s), c + P2(-0.45 * s, 0.18 * s)}, t,
      col);  // back arm
  cv.Polyline({c + P2(-0.12 * s, 0.0), c + P2(0.22 * s, -0.30 * s), c + P2(0.30 * s, -0.85 * s)}, t,
              col);  // front leg
  cv.Polyline({c + P2(-0.12 * s, 0.0), c + P2(-0.35 * s, -0.38 * s), c + P2(-0.70 * s, -0.55 * s)},
              t, col);  // back leg
}

// Arrow pointing in direction sign(dir) along x, length 2s.
void Arrow(Canvas& cv, P2 c, double s, double dir, Rgb col) {
  const double d = dir >= 0 ? 1.0 : -1.0;
  cv.Polygon({c + P2(-d * s, -0.22 * s), c + P2(d * 0.1 * s, -0.22 * s),
              c + P2(d * 0.1 * s, -0.6 * s), c + P2(d * s, 0.0), c + P2(d * 0.1 * s, 0.6 * s),
              c + P2(d * 0.1 * s, 0.22 * s), c + P2(-d * s, 0.22 * s)},
             col);
}

// Fire extinguisher silhouette about 2s tall (ISO 7010 F001), centred at c.
void ExtinguisherSilhouette(Canvas& cv, P2 c, double s, Rgb col) {
  const double bw = 0.55 * s;  // body width
  cv.Rect(c.x(), c.y() - 0.25 * s, bw, 1.30 * s, col);
  cv.Circle(c.x(), c.y() + 0.40 * s, bw / 2, col);
  cv.Rect(c.x(), c.y() + 0.72 * s, 0.22 * s, 0.25 * s, col);                  // valve
  cv.Line(c + P2(0.0, 0.90 * s), c + P2(0.45 * s, 0.98 * s), 0.12 * s, col);  // lever
  cv.Polyline(
      {c + P2(-0.08 * s, 0.80 * s), c + P2(-0.55 * s, 0.75 * s), c + P2(-0.75 * s, 0.35 * s)},
      0.10 * s, col);  // hose
  cv.Polygon({c + P2(-0.82 * s, 0.38 * s), c + P2(-0.68 * s, 0.38 * s), c + P2(-0.62 * s, 0.05 * s),
              c + P2(-0.88 * s, 0.05 * s)},
             col);  // nozzle
}

// Text-like bars (door plates, labels): rows of dark bars of varying length.
void TextBars(Canvas& cv, double x_left, double y_top, double width, double bar_h, int rows,
              Rgb col, unsigned seed) {
  // Fixed pseudo-random word lengths (deterministic LCG, no std:: distributions).
  unsigned s = seed * 2654435761u + 12345u;
  for (int r = 0; r < rows; ++r) {
    double x = x_left;
    const double y = y_top - r * bar_h * 2.0 - bar_h / 2;
    while (true) {
      s = s * 1664525u + 1013904223u;
      const double w = bar_h * (1.5 + (s >> 24) % 5);
      if (x + w > x_left + width) break;
      cv.Rect(x + w / 2, y, w, bar_h, col);
      x += w + bar_h * 0.8;
    }
  }
}

// Schuko socket face (CEE 7/3) centred at (cx, 0).
void SchukoFace(Canvas& cv, double cx, double cy) {
  cv.Circle(cx, cy, 0.0205, kClipGrey);
  cv.Circle(cx, cy, 0.0195, kCupGrey);
  cv.Circle(cx - 0.0095, cy, 0.0024, kHole);
  cv.Circle(cx + 0.0095, cy, 0.0024, kHole);
  cv.Rect(cx, cy + 0.0175, 0.008, 0.003, kClipGrey);
  cv.Rect(cx, cy - 0.0175, 0.008, 0.003, kClipGrey);
}

// ---------------------------------------------------------------------------------------------
// Geometry: convex prisms with outward-facing CCW triangles.

struct Solid {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3i> triangles;
  int material = 0;      // index into the model's body materials (ModelBuilder)
  bool textured = true;  // front-facing triangles carry the class texture
};

// Extrudes a convex polygon (CCW seen from +z) from z0 to z1: a closed prism.
Solid Prism(const std::vector<P2>& poly, double z0, double z1, int material, bool textured) {
  assert(poly.size() >= 3 && z1 > z0);
  Solid s;
  s.material = material;
  s.textured = textured;
  const int n = static_cast<int>(poly.size());
  for (const P2& p : poly) s.positions.emplace_back(p.x(), p.y(), z0);
  for (const P2& p : poly) s.positions.emplace_back(p.x(), p.y(), z1);
  for (int i = 1; i + 1 < n; ++i) {
    s.triangles.emplace_back(0, i + 1, i);          // back cap, normal -z
    s.triangles.emplace_back(n, n + i, n + i + 1);  // front cap, normal +z
  }
  for (int i = 0; i < n; ++i) {
    const int a = i, b = (i + 1) % n;
    s.triangles.emplace_back(a, b, n + b);
    s.triangles.emplace_back(a, n + b, n + a);
  }
  return s;
}

std::vector<P2> RectPoly(double cx, double cy, double w, double h) {
  return {{cx - w / 2, cy - h / 2},
          {cx + w / 2, cy - h / 2},
          {cx + w / 2, cy + h / 2},
          {cx - w / 2, cy + h / 2}};
}

// 32 segments with vertices on the axes, so the bounding box is exactly 2r.
std::vector<P2> CirclePoly(double cx, double cy, double r) {
  constexpr int kSegments = 32;
  std::vector<P2> out;
  for (int i = 0; i < kSegments; ++i) {
    const double a = 2 * kPi * i / kSegments;
    out.emplace_back(cx + r * std::cos(a), cy + r * std::sin(a));
  }
  return out;
}

Solid Box(double cx, double cy, double w, double h, double z0, double z1, int material,
          bool textured = true) {
  return Prism(RectPoly(cx, cy, w, h), z0, z1, material, textured);
}

// Cylinder whose axis is along z (discs on the wall, ceiling detectors).
Solid CylinderZ(double cx, double cy, double r, double z0, double z1, int material,
                bool textured = true) {
  return Prism(CirclePoly(cx, cy, r), z0, z1, material, textured);
}

// Cylinder whose axis is vertical (along y), axis at (cx, cz), from y0 to y1.
Solid CylinderY(double cx, double cz, double r, double y0, double y1, int material,
                bool textured = true) {
  // Build along z in (a, b, c) = (x, z, y), then swap: (x, y, z) = (a, c, b). The swap is a
  // reflection, so triangle winding is reversed to keep faces pointing outwards.
  Solid s = Prism(CirclePoly(cx, cz, r), y0, y1, material, textured);
  for (auto& p : s.positions) p = Eigen::Vector3d(p.x(), p.z(), p.y());
  for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

struct BodyMaterial {
  std::string name;
  Rgb colour;
  float roughness = 0.6f;
  float metallic = 0.0f;
};

struct ModelDef {
  std::vector<BodyMaterial> bodies;
  std::vector<Solid> solids;
};

// ---------------------------------------------------------------------------------------------
// The catalogue.

const std::vector<BscSpec>& Specs() {
  // default_mount_height: height of the model centre (local origin) above the floor.
  static const std::vector<BscSpec> k = {
      {"electrical_panel", Mounting::kWall, 0.50, 0.70, 0.12, 1.40, ""},
      {"socket_x1", Mounting::kWall, 0.08, 0.08, 0.04, 0.30, ""},
      {"socket_x2", Mounting::kWall, 0.15, 0.08, 0.04, 0.30, ""},
      {"socket_x4", Mounting::kWall, 0.29, 0.08, 0.04, 0.30, ""},
      {"built_in_socket", Mounting::kWall, 0.08, 0.08, 0.003, 0.30, ""},
      {"switch", Mounting::kWall, 0.08, 0.08, 0.012, 1.05, ""},
      {"fire_extinguisher", Mounting::kWall, 0.16, 0.55, 0.19, 0.90, ""},
      {"radiator", Mounting::kWall, 1.00, 0.60, 0.10, 0.45, ""},
      {"fire_alarm_switch", Mounting::kWall, 0.09, 0.09, 0.05, 1.40, ""},
      {"smoke_detector", Mounting::kCeiling, 0.11, 0.11, 0.05, 0.0, ""},
      {"exit_light", Mounting::kWall, 0.35, 0.15, 0.05, 2.30, ""},
      {"extinguisher_sign", Mounting::kWall, 0.20, 0.20, 0.003, 1.90, "fire_extinguisher"},
      {"fire_alarm_switch_sign", Mounting::kWall, 0.20, 0.20, 0.003, 1.90, "fire_alarm_switch"},
      {"fire_sign", Mounting::kWall, 0.20, 0.20, 0.003, 1.90, ""},
      {"exit_sign", Mounting::kWall, 0.30, 0.15, 0.003, 2.20, ""},
      {"electric_sign", Mounting::kWall, 0.20, 0.20 * 0.8660254037844386, 0.002, 1.90, ""},
      {"emergency_light", Mounting::kWall, 0.30, 0.12, 0.06, 2.30, ""},
      {"door_sign", Mounting::kWall, 0.15, 0.10, 0.003, 1.60, ""},
  };
  return k;
}

std::string ClassList() {
  std::string out;
  for (const auto& s : Specs()) out += (out.empty() ? "" : ", ") + s.class_name;
  return out;
}

const BscSpec& RequireSpec(const std::string& class_name) {
  const BscSpec* s = FindBsc(class_name);
  if (!s) {
    throw InputError("", "unknown building service component class", "'" + class_name + "'",
                     "one of: " + ClassList());
  }
  return *s;
}

// Geometry of each class (see the file comment for the frame).
ModelDef DefineGeometry(const BscSpec& s) {
  const std::string& c = s.class_name;
  const double w = s.width, h = s.height, d = s.depth;
  ModelDef m;
  if (c == "electrical_panel") {
    // Sheet-steel enclosure with a protruding lock handle on the right of the door.
    m.bodies = {{"enclosure", kPanelGrey, 0.5f}, {"handle", kBlack, 0.4f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d - 0.01, 0));
    m.solids.push_back(Box(0.20, 0, 0.025, 0.10, d - 0.01, d, 1, false));
  } else if (c == "socket_x1" || c == "socket_x2" || c == "socket_x4") {
    // Surface-mounted box with a slightly smaller cover frame on top (a bevel-like step).
    m.bodies = {{"housing", kWhite, 0.5f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d - 0.007, 0));
    m.solids.push_back(Box(0, 0, w - 0.008, h - 0.008, d - 0.007, d, 0));
  } else if (c == "built_in_socket") {
    m.bodies = {{"plate", kWhite, 0.5f}};  // flush: only the cover plate stands out
    m.solids.push_back(Box(0, 0, w, h, 0, d, 0));
  } else if (c == "switch") {
    m.bodies = {{"plate", kWhite, 0.5f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d - 0.004, 0));
    m.solids.push_back(Box(0, 0, 0.055, 0.055, d - 0.004, d, 0));  // rocker
  } else if (c == "fire_extinguisher") {
    // 6 kg extinguisher on a wall bracket; the cylinder stands off by the bracket depth.
    const double r = w / 2, bracket = d - w, body_top = h / 2 - 0.10;
    m.bodies = {{"cylinder", kSignalRed, 0.3f},
                {"valve", kBlack, 0.5f},
                {"bracket", kDarkGrey, 0.5f, 1.0f}};
    m.solids.push_back(CylinderY(0, bracket + r, r, -h / 2, body_top, 0));
    m.solids.push_back(CylinderY(0, bracket + r, 0.025, body_top, h / 2, 1, false));
    m.solids.push_back(Box(0, 0.10, 0.06, 0.10, 0, bracket, 2, false));
  } else if (c == "radiator") {
    // Panel radiator on two wall brackets with vertical convector fins in front.
    const double stand_off = 0.03, panel = 0.04;
    m.bodies = {{"steel", kWhite, 0.4f}, {"bracket", kDarkGrey, 0.5f, 1.0f}};
    m.solids.push_back(Box(-0.35, 0.15, 0.04, 0.06, 0, stand_off, 1, false));
    m.solids.push_back(Box(0.35, 0.15, 0.04, 0.06, 0, stand_off, 1, false));
    m.solids.push_back(Box(0, 0, w, h, stand_off, stand_off + panel, 0));
    constexpr int kFins = 20;
    const double pitch = w / kFins;
    for (int i = 0; i < kFins; ++i) {
      const double x = -w / 2 + (i + 0.5) * pitch;
      m.solids.push_back(Box(x, 0, 0.02, h - 0.04, stand_off + panel, d, 0));
    }
  } else if (c == "fire_alarm_switch") {
    // EN 54-11 manual call point: red back box and a slightly smaller front cover.
    m.bodies = {{"housing", kSignalRed, 0.4f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d - 0.008, 0));
    m.solids.push_back(Box(0, 0, w - 0.006, h - 0.006, d - 0.008, d, 0));
  } else if (c == "smoke_detector") {
    // Ceiling disc: mounting base plus the smaller sensing head.
    m.bodies = {{"housing", kWhite, 0.5f}};
    m.solids.push_back(CylinderZ(0, 0, w / 2, 0, d - 0.015, 0));
    m.solids.push_back(CylinderZ(0, 0, 0.04, d - 0.015, d, 0));
  } else if (c == "exit_light") {
    m.bodies = {{"housing", kWhite, 0.5f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d, 0));
  } else if (c == "emergency_light") {
    m.bodies = {{"housing", kWhite, 0.5f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d - 0.025, 0));
    m.solids.push_back(Box(0, 0, w - 0.03, h - 0.03, d - 0.025, d, 0));  // diffuser
  } else if (c == "electric_sign") {
    // Triangular ISO 7010 W012 plate.
    m.bodies = {{"plate", kWarningYellow, 0.5f}};
    m.solids.push_back(Prism({{-w / 2, -h / 2}, {w / 2, -h / 2}, {0, h / 2}}, 0, d, 0, true));
  } else if (c == "extinguisher_sign" || c == "fire_alarm_switch_sign" || c == "fire_sign") {
    m.bodies = {{"plate", kSignalRed, 0.5f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d, 0));
  } else if (c == "exit_sign") {
    m.bodies = {{"plate", kSafetyGreen, 0.5f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d, 0));
  } else if (c == "door_sign") {
    m.bodies = {{"plate", kWhite, 0.4f}};
    m.solids.push_back(Box(0, 0, w, h, 0, d, 0));
  } else {
    assert(false && "class without geometry");
  }
  return m;
}

Texture DrawElectricalPanel(const std::string& c, double w, double h) {
  Canvas cv(w, h, kPanelGrey);
  cv.RectOutline(0, 0, w - 0.02, h - 0.02, 0.003, kDarkGrey);  // door gap
  WarningTriangle(cv, P2(0, 0.20), 0.14);
  cv.Rect(0, 0.02, 0.16, 0.05, kPureWhite);  // circuit label
  TextBars(cv, -0.07, 0.035, 0.14, 0.006, 2, kTextGrey, 1);
  cv.Rect(0.20, 0, 0.035, 0.11, kDarkGrey);  // handle escutcheon
  cv.Circle(0.20, 0.03, 0.006, kBlack);      // lock cylinder
  return cv.ToTexture(c);
}

Texture DrawSocket(const std::string& c, double w, double h) {
  Canvas cv(w, h, kWhite);
  const int gangs = c == "socket_x2" ? 2 : c == "socket_x4" ? 4 : 1;
  const double pitch = 0.071;
  if (c != "built_in_socket") cv.RectOutline(0, 0, w - 0.008, h - 0.008, 0.001, kCupGrey);
  for (int g = 0; g < gangs; ++g) SchukoFace(cv, (g - (gangs - 1) / 2.0) * pitch, 0);
  return cv.ToTexture(c);
}

Texture DrawSwitch(const std::string& c, double w, double h) {
  Canvas cv(w, h, kWhite);
  cv.RectOutline(0, 0, 0.057, 0.057, 0.0015, kCupGrey);  // gap around the rocker
  cv.Rect(0, 0, 0.052, 0.052, kPureWhite);
  cv.Rect(0, 0.018, 0.010, 0.002, kClipGrey);  // "on" mark
  cv.Rect(0, -0.018, 0.010, 0.002, kClipGrey);
  return cv.ToTexture(c);
}

Texture DrawFireExtinguisher(const std::string& c, double w, double h) {
  Canvas cv(w, h, kSignalRed);
  cv.Rect(0, h / 2 - 0.05, 0.06, 0.10, kBlack);    // valve head (seen from the front)
  cv.Rect(-0.008, -0.02, 0.10, 0.20, kPureWhite);  // instruction label
  TextBars(cv, -0.05, 0.065, 0.085, 0.006, 4, kTextGrey, 2);
  cv.Rect(-0.03, -0.09, 0.025, 0.025, kSignalRed);  // fire-class pictograms
  cv.Rect(0.0, -0.09, 0.025, 0.025, kSafetyGreen);
  cv.Polyline({P2(0.02, 0.17), P2(0.058, 0.12), P2(0.058, -0.16)}, 0.012, kBlack);  // hose
  return cv.ToTexture(c);
}

Texture DrawRadiator(const std::string& c, double w, double h) {
  Canvas cv(w, h, Rgb{228, 228, 226});  // panel between fins, in the fins' shadow
  constexpr int kFins = 20;
  for (int i = 0; i < kFins; ++i)
    cv.Rect(-w / 2 + (i + 0.5) * w / kFins, 0, 0.02, h - 0.04, kWhite);
  cv.Rect(0, h / 2 - 0.01, w, 0.02, kWhite);
  cv.Rect(0, -h / 2 + 0.01, w, 0.02, kWhite);
  return cv.ToTexture(c);
}

Texture DrawFireAlarmSwitch(const std::string& c, double w, double h) {
  Canvas cv(w, h, kSignalRed);
  cv.Rect(0, 0, 0.05, 0.05, kPureWhite);  // frangible element
  cv.RectOutline(0, 0, 0.05, 0.05, 0.002, kBlack);
  // house with a flame (the EN 54-11 symbol)
  cv.Polygon({{-0.012, -0.014}, {0.012, -0.014}, {0.012, 0.004}, {0.0, 0.016}, {-0.012, 0.004}},
             kBlack);
  cv.Polygon(Place(UnitFlame(), P2(0, -0.005), 0.007), kPureWhite);
  return cv.ToTexture(c);
}

Texture DrawSmokeDetector(const std::string& c, double w, double h) {
  Canvas cv(w, h, kWhite);
  cv.Ring(0, 0, 0.041, 0.049, Rgb{175, 175, 172});  // smoke inlet vents
  for (int i = 0; i < 24; ++i) {                    // vent ribs
    const double a = 2 * kPi * i / 24;
    cv.Line(P2(0.041 * std::cos(a), 0.041 * std::sin(a)),
            P2(0.049 * std::cos(a), 0.049 * std::sin(a)), 0.002, kWhite);
  }
  cv.Ring(0, 0, 0.030, 0.032, Rgb{215, 215, 212});
  cv.Circle(0.022, 0.0, 0.0025, kSignalRed);  // status LED
  return cv.ToTexture(c);
}

Texture DrawExitLight(const std::string& c, double w, double h) {
  Canvas cv(w, h, kWhite);
  cv.Rect(0, 0, w - 0.02, h - 0.02, kSafetyGreen);
  Arrow(cv, P2(-0.10, 0), 0.045, -1.0, kPureWhite);
  RunningFigure(cv, P2(0.02, -0.005), 0.05, kPureWhite);
  cv.RectOutline(0.11, 0, 0.07, 0.11, 0.008, kPureWhite);  // door
  return cv.ToTexture(c);
}

Texture DrawEmergencyLight(const std::string& c, double w, double h) {
  Canvas cv(w, h, kWhite);
  cv.RectOutline(0, 0, w - 0.03, h - 0.03, 0.002, kCupGrey);
  cv.Rect(0, 0, w - 0.034, h - 0.034, kPureWhite);               // diffuser
  cv.Rect(0, -0.03, w - 0.05, 0.012, kSafetyGreen);              // green stripe
  cv.Circle(w / 2 - 0.025, h / 2 - 0.008, 0.002, kSafetyGreen);  // charge LED
  return cv.ToTexture(c);
}

Texture DrawExtinguisherSign(const std::string& c, double w, double h) {
  Canvas cv(w, h, kSignalRed);
  cv.RectOutline(0, 0, w - 0.008, h - 0.008, 0.004, kPureWhite);
  ExtinguisherSilhouette(cv, P2(0.005, -0.01), 0.07, kPureWhite);
  cv.Polygon(Place(UnitFlame(), P2(0.06, 0.05), 0.025), kPureWhite);
  return cv.ToTexture(c);
}

Texture DrawFireAlarmSwitchSign(const std::string& c, double w, double h) {
  Canvas cv(w, h, kSignalRed);
  cv.RectOutline(0, 0, w - 0.008, h - 0.008, 0.004, kPureWhite);
  cv.RectOutline(-0.02, -0.01, 0.09, 0.09, 0.01, kPureWhite);  // call point
  cv.Circle(-0.02, -0.01, 0.018, kPureWhite);
  for (int i = -1; i <= 1; ++i) {  // sounding waves
    const double a = i * 0.45;
    cv.Line(P2(0.04 + 0.01 * std::cos(a), 0.05 + 0.01 * std::sin(a)),
            P2(0.04 + 0.04 * std::cos(a), 0.05 + 0.04 * std::sin(a)), 0.008, kPureWhite);
  }
  cv.Polygon(Place(UnitFlame(), P2(0.05, -0.05), 0.022), kPureWhite);
  return cv.ToTexture(c);
}

Texture DrawFireSign(const std::string& c, double w, double h) {
  Canvas cv(w, h, kSignalRed);
  cv.RectOutline(0, 0, w - 0.008, h - 0.008, 0.004, kPureWhite);
  cv.Polygon(Place(UnitFlame(), P2(0, 0.01), 0.07), kPureWhite);
  cv.Rect(0, -0.07, 0.12, 0.01, kPureWhite);
  return cv.ToTexture(c);
}

Texture DrawExitSign(const std::string& c, double w, double h) {
  Canvas cv(w, h, kSafetyGreen);
  cv.RectOutline(0, 0, w - 0.008, h - 0.008, 0.003, kPureWhite);
  Arrow(cv, P2(-0.095, 0), 0.04, -1.0, kPureWhite);
  RunningFigure(cv, P2(0.01, -0.005), 0.05, kPureWhite);
  cv.RectOutline(0.095, 0, 0.065, 0.11, 0.008, kPureWhite);  // door
  return cv.ToTexture(c);
}

Texture DrawElectricSign(const std::string& c, double w, double h) {
  Canvas cv(w, h, kWarningYellow);
  // Triangle filling the plate: black border 12% of the side, yellow field, black bolt.
  cv.Polygon({{-w / 2, -h / 2}, {w / 2, -h / 2}, {0, h / 2}}, kBlack);
  const double s = 0.76;
  const P2 g(0, -h / 2 + h / 3);
  cv.Polygon({g + s * (P2(-w / 2, -h / 2) - g), g + s * (P2(w / 2, -h / 2) - g),
              g + s * (P2(0, h / 2) - g)},
             kWarningYellow);
  cv.Polygon(Place(UnitBolt(), g + P2(0, -0.004), 0.042), kBlack);
  return cv.ToTexture(c);
}

Texture DrawDoorSign(const std::string& c, double w, double h) {
  Canvas cv(w, h, kWhite);
  cv.RectOutline(0, 0, w, h, 0.003, Rgb{190, 190, 188});
  cv.Rect(-0.035, 0.025, 0.05, 0.022, kTextGrey);  // room number
  TextBars(cv, -0.06, -0.005, 0.12, 0.007, 3, kTextGrey, 3);
  return cv.ToTexture(c);
}

// Pictogram of each class, drawn in the model's (x, y) frame over its whole bounding box.
Texture DrawTexture(const BscSpec& s) {
  const std::string& c = s.class_name;
  const double w = s.width, h = s.height;
  if (c == "electrical_panel") return DrawElectricalPanel(c, w, h);
  if (c == "socket_x1" || c == "socket_x2" || c == "socket_x4" || c == "built_in_socket")
    return DrawSocket(c, w, h);
  if (c == "switch") return DrawSwitch(c, w, h);
  if (c == "fire_extinguisher") return DrawFireExtinguisher(c, w, h);
  if (c == "radiator") return DrawRadiator(c, w, h);
  if (c == "fire_alarm_switch") return DrawFireAlarmSwitch(c, w, h);
  if (c == "smoke_detector") return DrawSmokeDetector(c, w, h);
  if (c == "exit_light") return DrawExitLight(c, w, h);
  if (c == "emergency_light") return DrawEmergencyLight(c, w, h);
  if (c == "extinguisher_sign") return DrawExtinguisherSign(c, w, h);
  if (c == "fire_alarm_switch_sign") return DrawFireAlarmSwitchSign(c, w, h);
  if (c == "fire_sign") return DrawFireSign(c, w, h);
  if (c == "exit_sign") return DrawExitSign(c, w, h);
  if (c == "electric_sign") return DrawElectricSign(c, w, h);
  if (c == "door_sign") return DrawDoorSign(c, w, h);
  assert(false && "class without texture");
  return {};
}

// ---------------------------------------------------------------------------------------------
// Orthographic rendering of a model along -z (for the object models).

std::array<double, 3> SampleTexture(const Texture& t, const Eigen::Vector2d& uv) {
  // Bilinear, clamp to edge; texel centres at (i + 0.5) / width.
  const double x = std::clamp(uv.x(), 0.0, 1.0) * t.width - 0.5;
  const double y = std::clamp(uv.y(), 0.0, 1.0) * t.height - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  std::array<double, 3> out{0, 0, 0};
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      const int xi = std::clamp(x0 + dx, 0, t.width - 1);
      const int yi = std::clamp(y0 + dy, 0, t.height - 1);
      const double wgt = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
      const std::uint8_t* p = &t.rgba[4 * (static_cast<std::size_t>(yi) * t.width + xi)];
      for (int k = 0; k < 3; ++k) out[k] += wgt * p[k] / 255.0;
    }
  }
  return out;
}

}  // namespace

const std::vector<BscSpec>& BscCatalogue() { return Specs(); }

const BscSpec* FindBsc(const std::string& class_name) {
  for (const auto& s : Specs())
    if (s.class_name == class_name) return &s;
  return nullptr;
}

Scene BuildBscModel(const std::string& class_name) {
  const BscSpec& spec = RequireSpec(class_name);
  const ModelDef def = DefineGeometry(spec);

  Scene scene;
  scene.source = "bsc_catalogue:" + class_name;
  scene.textures.push_back(DrawTexture(spec));

  // Material 0: the front face (texture × white); 1 + i: body material i.
  Material face;
  face.name = class_name + "_face";
  face.base_color = Eigen::Vector4f(1, 1, 1, 1);
  face.base_color_texture = 0;
  face.roughness = def.bodies.empty() ? 0.5f : def.bodies[0].roughness;
  scene.materials.push_back(face);
  for (const auto& b : def.bodies) {
    Material m;
    m.name = class_name + "_" + b.name;
    m.base_color = LinearColour(b.colour);
    m.roughness = b.roughness;
    m.metallic = b.metallic;
    scene.materials.push_back(m);
  }

  // Part 0 = textured face, part 1 + i = body material i. Empty parts are dropped at the end.
  std::vector<MeshPart> parts(1 + def.bodies.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    MeshPart& p = parts[i];
    p.name = class_name + (i == 0 ? std::string("_face") : "_" + def.bodies[i - 1].name);
    p.element_class = ElementClass::kServiceComponent;
    p.subclass = class_name;
    p.material = static_cast<int>(i);
  }
  const double w = spec.width, h = spec.height;
  for (std::size_t si = 0; si < def.solids.size(); ++si) {
    const Solid& s = def.solids[si];
    std::map<std::pair<int, int>, int> remap;  // (part, solid vertex) -> part vertex
    for (const auto& t : s.triangles) {
      const Eigen::Vector3d n =
          (s.positions[t[1]] - s.positions[t[0]]).cross(s.positions[t[2]] - s.positions[t[0]]);
      const bool front = s.textured && n.z() > 0.5 * n.norm();
      const int pi = front ? 0 : 1 + s.material;
      MeshPart& part = parts[pi];
      Eigen::Vector3i tri;
      for (int k = 0; k < 3; ++k) {
        auto [it, added] = remap.try_emplace({pi, t[k]}, static_cast<int>(part.positions.size()));
        if (added) {
          const Eigen::Vector3d& p = s.positions[t[k]];
          part.positions.push_back(p.cast<float>());
          if (front) {
            part.uvs.emplace_back(static_cast<float>((p.x() + w / 2) / w),
                                  static_cast<float>((h / 2 - p.y()) / h));
          }
        }
        tri[k] = it->second;
      }
      part.triangles.push_back(tri);
    }
  }
  for (auto& p : parts)
    if (!p.triangles.empty()) scene.parts.push_back(std::move(p));
  return scene;
}

interfaces::ObjectModel MakeObjectModel(const std::string& class_name, double pixel_size) {
  const BscSpec& spec = RequireSpec(class_name);
  if (!std::isfinite(pixel_size) || pixel_size <= 0.0 ||
      std::max(spec.width, spec.height) / pixel_size > 8192.0) {
    throw InputError("", "object model pixel size out of range", std::to_string(pixel_size),
                     "a pixel size in (0, 1] m giving at most 8192 pixels per side");
  }
  const Scene scene = BuildBscModel(class_name);

  interfaces::ObjectModel m;
  m.class_name = class_name;
  m.mounting = spec.mounting;
  m.width = spec.width;
  m.height = spec.height;
  m.depth = spec.depth;
  m.marks = spec.marks;
  m.pixel_size = pixel_size;
  // 1e-9 guards against 0.08 / 0.002 = 40.000000000000007.
  m.image_width = std::max(1, static_cast<int>(std::ceil(spec.width / pixel_size - 1e-9)));
  m.image_height = std::max(1, static_cast<int>(std::ceil(spec.height / pixel_size - 1e-9)));
  const int nx = m.image_width, ny = m.image_height;
  m.colour_rgb.assign(static_cast<std::size_t>(nx) * ny * 3, 0);
  m.depth_m.assign(static_cast<std::size_t>(nx) * ny, 0.0f);
  std::vector<double> zbuf(static_cast<std::size_t>(nx) * ny, -1.0);

  // Pixel (i, j) looks along -z through x = (i + 0.5 - nx/2) ps, y = (ny/2 - j - 0.5) ps.
  for (const MeshPart& part : scene.parts) {
    const Material* mat = part.material >= 0 ? &scene.materials[part.material] : nullptr;
    const Texture* tex = (mat && mat->base_color_texture >= 0 && !part.uvs.empty())
                             ? &scene.textures[mat->base_color_texture]
                             : nullptr;
    for (const auto& t : part.triangles) {
      const Eigen::Vector3d a = part.positions[t[0]].cast<double>();
      const Eigen::Vector3d b = part.positions[t[1]].cast<double>();
      const Eigen::Vector3d c = part.positions[t[2]].cast<double>();
      // Signed doubled area in xy; > 0 for triangles facing the viewer (+z).
      const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
      if (area <= 1e-14) continue;
      const double xmin = std::min({a.x(), b.x(), c.x()}), xmax = std::max({a.x(), b.x(), c.x()});
      const double ymin = std::min({a.y(), b.y(), c.y()}), ymax = std::max({a.y(), b.y(), c.y()});
      const int i0 = std::max(0, static_cast<int>(std::floor(xmin / pixel_size + nx / 2.0 - 0.5)));
      const int i1 =
          std::min(nx - 1, static_cast<int>(std::ceil(xmax / pixel_size + nx / 2.0 - 0.5)));
      const int j0 = std::max(0, static_cast<int>(std::floor(ny / 2.0 - ymax / pixel_size - 0.5)));
      const int j1 =
          std::min(ny - 1, static_cast<int>(std::ceil(ny / 2.0 - ymin / pixel_size - 0.5)));
      for (int j = j0; j <= j1; ++j) {
        const double y = (ny / 2.0 - j - 0.5) * pixel_size;
        for (int i = i0; i <= i1; ++i) {
          const double x = (i + 0.5 - nx / 2.0) * pixel_size;
          // Barycentric coordinates; edges are inclusive so shared edges leave no cracks.
          const double l0 = ((b.x() - x) * (c.y() - y) - (b.y() - y) * (c.x() - x)) / area;
          const double l1 = ((c.x() - x) * (a.y() - y) - (c.y() - y) * (a.x() - x)) / area;
          const double l2 = 1.0 - l0 - l1;
          constexpr double kEps = -1e-9;
          if (l0 < kEps || l1 < kEps || l2 < kEps) continue;
          const double z = l0 * a.z() + l1 * b.z() + l2 * c.z();
          const std::size_t idx = static_cast<std::size_t>(j) * nx + i;
          if (z <= zbuf[idx]) continue;
          zbuf[idx] = z;
          std::array<double, 3> srgb{1, 1, 1};
          if (tex) {
            const Eigen::Vector2d uv = l0 * part.uvs[t[0]].cast<double>() +
                                       l1 * part.uvs[t[1]].cast<double>() +
                                       l2 * part.uvs[t[2]].cast<double>();
            srgb = SampleTexture(*tex, uv);
          }
          for (int k = 0; k < 3; ++k) {
            const double factor = mat ? mat->base_color[k] : 0.8;
            const double lin = factor * SrgbToLinear(srgb[k]);
            m.colour_rgb[3 * idx + k] =
                static_cast<std::uint8_t>(std::lround(255.0 * LinearToSrgb(lin)));
          }
          m.depth_m[idx] = static_cast<float>(std::max(0.0, z));
        }
      }
    }
  }
  return m;
}

interfaces::ObjectModelCatalogue MakeObjectModelCatalogue(double pixel_size) {
  interfaces::ObjectModelCatalogue cat;
  for (const auto& s : Specs()) cat.models.push_back(MakeObjectModel(s.class_name, pixel_size));
  return cat;
}

}  // namespace mopad::scenes
