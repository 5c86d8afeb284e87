#include "scenes/plan_view.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "common/error.h"

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using Rgb = std::array<std::uint8_t, 3>;

constexpr int kMaxPixels = 8000;

Rgb ClassColour(ElementClass c) {
  switch (c) {
    case ElementClass::kFurniture:
      return {196, 164, 120};
    case ElementClass::kDoorLeaf:
      return {140, 90, 40};
    case ElementClass::kDoorFrame:
      return {120, 80, 40};
    case ElementClass::kWindowFrame:
    case ElementClass::kWindowGlass:
      return {120, 170, 230};
    case ElementClass::kServiceComponent:
      return {220, 0, 220};
    case ElementClass::kColumn:
      return {90, 90, 90};
    default:
      return {215, 215, 215};
  }
}

// Pastel colour of room k (fixed table, deterministic).
Rgb RoomColour(int k) {
  static const Rgb kTable[] = {{255, 236, 179}, {200, 230, 201}, {187, 222, 251}, {248, 187, 208},
                               {225, 190, 231}, {255, 224, 178}, {178, 235, 242}, {220, 237, 200},
                               {255, 205, 210}, {209, 196, 233}};
  return kTable[static_cast<std::size_t>(k) % (sizeof(kTable) / sizeof(kTable[0]))];
}

class Canvas {
 public:
  Canvas(const Eigen::AlignedBox2d& box, double px) : box_(box), px_(px) {
    w_ = static_cast<int>(std::ceil(box.sizes().x() / px));
    h_ = static_cast<int>(std::ceil(box.sizes().y() / px));
    if (w_ > kMaxPixels || h_ > kMaxPixels || w_ <= 0 || h_ <= 0)
      throw InputError("", "plan view too large", std::to_string(w_) + " x " + std::to_string(h_),
                       "at most " + std::to_string(kMaxPixels) + " pixels a side");
    rgb_.assign(static_cast<std::size_t>(w_) * h_, Rgb{255, 255, 255});
    z_.assign(rgb_.size(), -std::numeric_limits<double>::infinity());
  }
  // Pixel coordinates (x right, y down) of a world point.
  Vector2d P(const Vector3d& p) const {
    return {(p.x() - box_.min().x()) / px_, (box_.max().y() - p.y()) / px_};
  }
  void Dot(int x, int y, const Rgb& c) {
    if (x >= 0 && y >= 0 && x < w_ && y < h_) rgb_[static_cast<std::size_t>(y) * w_ + x] = c;
  }
  void Square(const Vector2d& p, int r, const Rgb& c) {
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx)
        Dot(static_cast<int>(std::floor(p.x())) + dx, static_cast<int>(std::floor(p.y())) + dy, c);
  }
  void Line(const Vector2d& a, const Vector2d& b, const Rgb& c, int r = 0) {
    const int n = static_cast<int>(std::ceil((b - a).norm() * 2.0)) + 1;
    for (int i = 0; i <= n; ++i) {
      const Vector2d p = a + (b - a) * (static_cast<double>(i) / n);
      if (r == 0)
        Dot(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())), c);
      else
        Square(p, r, c);
    }
  }
  // Z-buffered triangle: the highest surface below the cut wins.
  void Triangle(const Vector3d& a, const Vector3d& b, const Vector3d& c, double cut,
                const Rgb& col) {
    const Vector2d pa = P(a), pb = P(b), pc = P(c);
    const double den =
        (pb.x() - pa.x()) * (pc.y() - pa.y()) - (pc.x() - pa.x()) * (pb.y() - pa.y());
    if (std::abs(den) < 1e-9) return;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({pa.x(), pb.x(), pc.x()}))));
    const int x1 =
        std::min(w_ - 1, static_cast<int>(std::ceil(std::max({pa.x(), pb.x(), pc.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({pa.y(), pb.y(), pc.y()}))));
    const int y1 =
        std::min(h_ - 1, static_cast<int>(std::ceil(std::max({pa.y(), pb.y(), pc.y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Vector2d q(x + 0.5, y + 0.5);
        const double l1 =
            ((q.x() - pa.x()) * (pc.y() - pa.y()) - (pc.x() - pa.x()) * (q.y() - pa.y())) / den;
        const double l2 =
            ((pb.x() - pa.x()) * (q.y() - pa.y()) - (q.x() - pa.x()) * (pb.y() - pa.y())) / den;
        const double l0 = 1.0 - l1 - l2;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        const double z = l0 * a.z() + l1 * b.z() + l2 * c.z();
        const std::size_t i = static_cast<std::size_t>(y) * w_ + x;
        if (z > cut || z <= z_[i]) continue;
        z_[i] = z;
        rgb_[i] = col;
      }
  }
  Texture Take() const {
    Texture t;
    t.name = "plan";
    t.width = w_;
    t.height = h_;
    t.repeat = false;
    t.rgba.reserve(rgb_.size() * 4);
    for (const Rgb& c : rgb_) t.rgba.insert(t.rgba.end(), {c[0], c[1], c[2], 255});
    return t;
  }

 private:
  Eigen::AlignedBox2d box_;
  double px_;
  int w_ = 0, h_ = 0;
  std::vector<Rgb> rgb_;
  std::vector<double> z_;
};

}  // namespace

void PlanViewParams::Validate() const {
  if (!(pixel_size > 0.0 && pixel_size <= 1.0))
    throw InputError("", "plan view pixel_size out of range", std::to_string(pixel_size),
                     "(0, 1] m");
  if (!std::isfinite(cut_height))
    throw InputError("", "plan view cut_height not finite", std::to_string(cut_height), "m");
  if (!(margin >= 0.0 && margin <= 20.0))
    throw InputError("", "plan view margin out of range", std::to_string(margin), "[0, 20] m");
}

Texture RenderPlanView(const Scene& scene, const GroundTruth& truth, const PlanViewParams& p) {
  p.Validate();
  if (truth.rooms.empty()) throw InputError("", "plan view needs rooms", "0 rooms", ">= 1");
  Eigen::AlignedBox2d box;
  for (const Room& r : truth.rooms)
    for (const auto& v : r.polygon) box.extend(v);
  box.min() -= Vector2d::Constant(p.margin);
  box.max() += Vector2d::Constant(p.margin);
  Canvas canvas(box, p.pixel_size);
  std::map<std::string, int> room_index;
  for (std::size_t i = 0; i < truth.rooms.size(); ++i)
    room_index[truth.rooms[i].id] = static_cast<int>(i);

  // 1. Surfaces below the cut, seen from above.
  for (const MeshPart& part : scene.parts) {
    Rgb col = ClassColour(part.element_class);
    if (part.element_class == ElementClass::kFloor && room_index.count(part.room))
      col = RoomColour(room_index[part.room]);
    for (const auto& t : part.triangles) {
      const Vector3d a = part.positions[t[0]].cast<double>(),
                     b = part.positions[t[1]].cast<double>(),
                     c = part.positions[t[2]].cast<double>();
      canvas.Triangle(a, b, c, p.cut_height, col);
    }
  }
  // 2. Section of every triangle at the cut height.
  for (const MeshPart& part : scene.parts) {
    const bool glass = part.element_class == ElementClass::kWindowGlass ||
                       part.element_class == ElementClass::kWindowFrame;
    const Rgb col = glass ? Rgb{30, 90, 200} : Rgb{0, 0, 0};
    for (const auto& t : part.triangles) {
      std::vector<Vector3d> hits;
      for (int k = 0; k < 3; ++k) {
        const Vector3d a = part.positions[t[k]].cast<double>();
        const Vector3d b = part.positions[t[(k + 1) % 3]].cast<double>();
        const double da = a.z() - p.cut_height, db = b.z() - p.cut_height;
        if ((da < 0 && db >= 0) || (da >= 0 && db < 0))
          hits.push_back(a + da / (da - db) * (b - a));
      }
      if (hits.size() == 2) canvas.Line(canvas.P(hits[0]), canvas.P(hits[1]), col);
    }
  }
  // 3. The truth.
  for (const StructuralElement& e : truth.elements) {
    if (e.element_class != ElementClass::kWall) continue;
    const Vector3d in = e.normal * (1.5 * p.pixel_size);
    canvas.Line(canvas.P(e.origin + in), canvas.P(e.origin + e.length * e.u_axis + in),
                {220, 30, 30});
  }
  for (const Opening& o : truth.openings) {
    if (o.corners.size() != 4) continue;
    const bool door = o.type == OpeningType::kDoor;
    const Rgb col = door ? Rgb{0, 160, 0} : Rgb{0, 90, 255};
    canvas.Line(canvas.P(o.corners[0]), canvas.P(o.corners[3]), col, 1);
    if (door) canvas.Square(canvas.P(o.hinge_point), 3, {0, 120, 0});
  }
  for (const ServiceComponent& s : truth.service_components)
    canvas.Square(canvas.P(s.centre), 3, {220, 0, 220});
  for (const Room& r : truth.rooms)
    for (const auto& v : r.polygon)
      canvas.Square(canvas.P(Vector3d(v.x(), v.y(), 0.0)), 2, {60, 60, 60});
  return canvas.Take();
}

}  // namespace mopad::scenes
