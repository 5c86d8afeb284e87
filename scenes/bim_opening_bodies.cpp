// The bodies of the IfcOpeningElements that doors and windows fill, read from the STEP text:
// the file's own statement of where each hole is, independent of the reader's boolean cut
// (scenes/bim_import_internal.h, docs/scene-import.md).
#include <cmath>
#include <cstdlib>
#include <optional>

#include "scenes/bim_import_internal.h"

namespace mopad::scenes::bim {
namespace {

// Placement chains and representation trees are shallow; a deeper one is a cycle.
constexpr int kMaxDepth = 32;

class BodyReader {
 public:
  explicit BodyReader(const StepIndex& step) : step_(step) {}

  // The origin of the opening element's placement, file units.
  std::optional<Vector3d> Origin(unsigned long opening) const {
    const std::vector<std::string> a = Args(opening);
    if (a.size() < 6) return std::nullopt;
    const std::optional<Eigen::Isometry3d> place = Placement(Ref(a[5]), 0);
    if (!place) return std::nullopt;
    return place->translation();
  }

  // Corners of the opening element's body in the file's world frame, file units; nullopt when
  // its body uses anything but extruded rectangles or closed polylines.
  std::optional<std::vector<Vector3d>> Corners(unsigned long opening) const {
    const std::vector<std::string> a = Args(opening);
    // (GlobalId, OwnerHistory, Name, Description, ObjectType, ObjectPlacement, Representation, ..)
    if (a.size() < 7) return std::nullopt;
    const std::optional<Eigen::Isometry3d> place = Placement(Ref(a[5]), 0);
    if (!place) return std::nullopt;
    const std::vector<std::string> shape = Args(Ref(a[6]));  // IfcProductDefinitionShape
    if (shape.size() < 3) return std::nullopt;
    std::vector<Vector3d> out;
    for (unsigned long rep : StepRefs(shape[2])) {
      const std::vector<std::string> r = Args(rep);  // IfcShapeRepresentation
      if (r.size() < 4 || StepString(r[1]) != "Body") continue;
      for (unsigned long item : StepRefs(r[3]))
        if (!Extrusion(item, *place, &out)) return std::nullopt;
    }
    if (out.empty()) return std::nullopt;
    return out;
  }

 private:
  std::string Entity(unsigned long id) const {
    const auto it = step_.bodies.find(id);
    return it == step_.bodies.end() ? "" : EntityOf(it->second);
  }
  std::vector<std::string> Args(unsigned long id) const {
    const auto it = step_.bodies.find(id);
    return it == step_.bodies.end() ? std::vector<std::string>{} : Attributes(it->second);
  }
  static unsigned long Ref(const std::string& attr) {
    const std::vector<unsigned long> r = StepRefs(attr);
    return r.empty() ? 0 : r[0];
  }
  // The numbers of a list attribute "(0.,0.6,1.E-3)".
  static std::vector<double> Numbers(const std::string& attr) {
    std::vector<double> out;
    const char* c = attr.c_str();
    while (*c) {
      if (*c == '(' || *c == ')' || *c == ',' || *c == ' ') {
        ++c;
        continue;
      }
      char* end = nullptr;
      const double v = std::strtod(c, &end);
      if (end == c) return {};
      out.push_back(v);
      c = end;
    }
    return out;
  }
  // IfcCartesianPoint / IfcDirection coordinates, 2D or 3D (z 0 for 2D).
  std::optional<Vector3d> Coordinates(unsigned long id, const char* entity) const {
    if (Entity(id) != entity) return std::nullopt;
    const std::vector<std::string> a = Args(id);
    if (a.empty()) return std::nullopt;
    const std::vector<double> v = Numbers(a[0]);
    if (v.size() < 2 || v.size() > 3) return std::nullopt;
    const Vector3d p(v[0], v[1], v.size() == 3 ? v[2] : 0.0);
    if (!p.allFinite()) return std::nullopt;
    return p;
  }
  // IfcAxis2Placement3D / 2D: location, z axis (3D only), x direction; defaults per IFC.
  std::optional<Eigen::Isometry3d> Axis2(unsigned long id) const {
    const std::string entity = Entity(id);
    const bool three = entity == "IFCAXIS2PLACEMENT3D";
    if (!three && entity != "IFCAXIS2PLACEMENT2D") return std::nullopt;
    const std::vector<std::string> a = Args(id);
    if (a.empty()) return std::nullopt;
    const std::optional<Vector3d> loc = Coordinates(Ref(a[0]), "IFCCARTESIANPOINT");
    if (!loc) return std::nullopt;
    Vector3d z = Vector3d::UnitZ(), x = Vector3d::UnitX();
    const std::size_t xi = three ? 2 : 1;
    if (three && a.size() > 1 && Ref(a[1]) != 0) {
      const std::optional<Vector3d> d = Coordinates(Ref(a[1]), "IFCDIRECTION");
      if (!d) return std::nullopt;
      z = *d;
    }
    if (a.size() > xi && Ref(a[xi]) != 0) {
      const std::optional<Vector3d> d = Coordinates(Ref(a[xi]), "IFCDIRECTION");
      if (!d) return std::nullopt;
      x = *d;
    }
    if (z.norm() < 1e-12) return std::nullopt;
    z.normalize();
    x -= x.dot(z) * z;  // IFC: the x direction is projected onto the plane normal to z
    if (x.norm() < 1e-9) return std::nullopt;
    x.normalize();
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear().col(0) = x;
    t.linear().col(1) = z.cross(x);
    t.linear().col(2) = z;
    t.translation() = *loc;
    return t;
  }
  // IfcLocalPlacement chain to the world.
  std::optional<Eigen::Isometry3d> Placement(unsigned long id, int depth) const {
    if (id == 0) return Eigen::Isometry3d::Identity();
    if (depth > kMaxDepth || Entity(id) != "IFCLOCALPLACEMENT") return std::nullopt;
    const std::vector<std::string> a = Args(id);
    if (a.size() < 2) return std::nullopt;
    const std::optional<Eigen::Isometry3d> parent = Placement(Ref(a[0]), depth + 1);
    const std::optional<Eigen::Isometry3d> own = Axis2(Ref(a[1]));
    if (!parent || !own) return std::nullopt;
    return *parent * *own;
  }
  // The outline of a profile in its own plane: a rectangle or a closed polyline.
  std::optional<std::vector<Vector3d>> Profile(unsigned long id) const {
    const std::string entity = Entity(id);
    const std::vector<std::string> a = Args(id);
    std::vector<Vector3d> out;
    if (entity == "IFCRECTANGLEPROFILEDEF" && a.size() >= 5) {
      // (ProfileType, ProfileName, Position, XDim, YDim)
      Eigen::Isometry3d pos = Eigen::Isometry3d::Identity();
      if (Ref(a[2]) != 0) {
        const std::optional<Eigen::Isometry3d> p = Axis2(Ref(a[2]));
        if (!p) return std::nullopt;
        pos = *p;
      }
      const std::vector<double> xd = Numbers(a[3]), yd = Numbers(a[4]);
      if (xd.size() != 1 || yd.size() != 1 || !(xd[0] > 0.0) || !(yd[0] > 0.0)) return std::nullopt;
      for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
        out.push_back(pos * Vector3d(0.5 * sx * xd[0], 0.5 * sy * yd[0], 0.0));
      return out;
    }
    if (entity == "IFCARBITRARYCLOSEDPROFILEDEF" && a.size() >= 3) {
      const unsigned long curve = Ref(a[2]);
      if (Entity(curve) != "IFCPOLYLINE") return std::nullopt;
      const std::vector<std::string> c = Args(curve);
      if (c.empty()) return std::nullopt;
      for (unsigned long pt : StepRefs(c[0])) {
        const std::optional<Vector3d> p = Coordinates(pt, "IFCCARTESIANPOINT");
        if (!p) return std::nullopt;
        out.push_back(*p);
      }
      if (out.size() < 3) return std::nullopt;
      return out;
    }
    return std::nullopt;
  }
  // IfcExtrudedAreaSolid(SweptArea, Position, ExtrudedDirection, Depth): its corners appended.
  bool Extrusion(unsigned long id, const Eigen::Isometry3d& place,
                 std::vector<Vector3d>* out) const {
    if (Entity(id) != "IFCEXTRUDEDAREASOLID") return false;
    const std::vector<std::string> a = Args(id);
    if (a.size() < 4) return false;
    const std::optional<std::vector<Vector3d>> profile = Profile(Ref(a[0]));
    Eigen::Isometry3d pos = Eigen::Isometry3d::Identity();
    if (Ref(a[1]) != 0) {
      const std::optional<Eigen::Isometry3d> p = Axis2(Ref(a[1]));
      if (!p) return false;
      pos = *p;
    }
    const std::optional<Vector3d> dir = Coordinates(Ref(a[2]), "IFCDIRECTION");
    const std::vector<double> depth = Numbers(a[3]);
    if (!profile || !dir || depth.size() != 1 || !(depth[0] > 0.0) || dir->norm() < 1e-12)
      return false;
    const Vector3d step = dir->normalized() * depth[0];
    for (const Vector3d& p : *profile) {
      out->push_back(place * pos * p);
      out->push_back(place * pos * Vector3d(p + step));
    }
    return true;
  }

  const StepIndex& step_;
};

}  // namespace

std::vector<OpeningBody> OpeningBodies(const StepIndex& step, double scale) {
  std::map<unsigned long, std::string> filling_of;  // opening #id -> the filling's GlobalId
  for (const auto& [id, body] : step.bodies) {
    if (EntityOf(body) != "IFCRELFILLSELEMENT") continue;
    // (GlobalId, OwnerHistory, Name, Description, RelatingOpeningElement, RelatedBuildingElement)
    const std::vector<std::string> a = Attributes(body);
    if (a.size() < 6) continue;
    const std::vector<unsigned long> opening = StepRefs(a[4]), filling = StepRefs(a[5]);
    if (opening.size() != 1 || filling.size() != 1) continue;
    const auto it = step.bodies.find(filling[0]);
    if (it == step.bodies.end()) continue;
    const std::vector<std::string> fa = Attributes(it->second);
    if (!fa.empty() && StepString(fa[0]).size() == kGuidLength)
      filling_of[opening[0]] = StepString(fa[0]);
  }
  const BodyReader reader(step);
  std::vector<OpeningBody> out;
  for (const auto& [id, body] : step.bodies) {
    if (EntityOf(body) != "IFCOPENINGELEMENT" && EntityOf(body) != "IFCOPENINGSTANDARDCASE")
      continue;
    OpeningBody b;
    const auto f = filling_of.find(id);
    if (f != filling_of.end()) b.filling = f->second;
    if (std::optional<std::vector<Vector3d>> corners = reader.Corners(id)) {
      b.corners = std::move(*corners);
    } else if (std::optional<Vector3d> origin = reader.Origin(id)) {
      b.corners = {*origin};
      b.complete = false;
    } else {
      continue;
    }
    for (Vector3d& c : b.corners) c *= scale;
    out.push_back(std::move(b));
  }
  return out;
}

}  // namespace mopad::scenes::bim
