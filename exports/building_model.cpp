#include "exports/building_model.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "common/polygon.h"

namespace mopad::exports {
namespace {

using Json = nlohmann::ordered_json;
using modelling::PatchClass;

double SignedPlanArea(const std::vector<Eigen::Vector3d>& poly) {
  double a2 = 0.0;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const auto& a = poly[k];
    const auto& b = poly[(k + 1) % poly.size()];
    a2 += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * a2;
}

// Counter-clockwise seen from above.
std::vector<Eigen::Vector3d> PlanCcw(std::vector<Eigen::Vector3d> poly) {
  if (SignedPlanArea(poly) < 0) std::reverse(poly.begin(), poly.end());
  return poly;
}

// The convex hull in plan of `pts` (common's ConvexHull, collinear points within 1e-12 m^2
// dropped), counter-clockwise, at height z. Fewer than 3 distinct points make no footprint:
// one point gives none, several the first and the last in (x, y) order.
std::vector<Eigen::Vector3d> PlanHull(const std::vector<Eigen::Vector2d>& pts, double z) {
  std::vector<Eigen::Vector2d> hull = ConvexHull(pts, 1e-12);
  if (hull.size() < 3) {
    hull.clear();
    if (pts.size() >= 2) {
      const auto [first, last] = std::minmax_element(
          pts.begin(), pts.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
            return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
          });
      hull = {*first, *last};
    }
  }
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : hull) out.emplace_back(p.x(), p.y(), z);
  return out;
}

std::vector<Eigen::Vector3d> ToExport(const Eigen::Isometry3d& X_EM,
                                      const std::vector<Eigen::Vector3d>& poly) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : poly) out.push_back(X_EM * p);
  return out;
}

// "column_3_face_2" -> "column_3"; "" when the id does not name a column face.
std::string ColumnName(const std::string& patch_id) {
  const auto face = patch_id.find("_face_");
  return patch_id.rfind("column_", 0) == 0 && face != std::string::npos ? patch_id.substr(0, face)
                                                                        : "";
}

void AddPatches(const ModelSet& set, std::vector<Element>& out) {
  std::map<std::string, std::size_t> columns;  // column name -> index in out
  for (const auto& p : set.sm3.patches) {
    if (PolygonArea3d(p.polygon) < 1e-6) continue;
    Element e;
    e.room = set.id;
    e.polygon = ToExport(set.X_EM, p.polygon);
    e.normal = (set.X_EM.linear() * p.plane.n).normalized();
    e.properties = {
        {"patch", p.id}, {"support", p.support}, {"rms_m", p.rms}, {"fitted", p.fitted}};
    if (p.patch_class == PatchClass::kColumn) {
      const std::string name = ColumnName(p.id).empty() ? p.id : ColumnName(p.id);
      auto it = columns.find(name);
      if (it == columns.end()) {
        e.id = set.id + "/" + name;
        e.class_name = "column";
        e.kind = ElementKind::kColumn;
        e.properties = {{"faces", Json::array()}};
        it = columns.emplace(name, out.size()).first;
        out.push_back(std::move(e));
      }
      Element& c = out[it->second];
      c.properties["faces"].push_back(p.id);
      // Keep every face vertex for now; the footprint is their hull (below).
      for (const auto& v : ToExport(set.X_EM, p.polygon)) c.polygon.push_back(v);
      continue;
    }
    e.id = set.id + "/" + p.id;
    if (const auto t = set.wall_thickness.find(p.id); t != set.wall_thickness.end())
      e.properties["thickness_m"] = t->second;
    e.class_name = modelling::ToString(p.patch_class);
    e.kind = p.patch_class == PatchClass::kWall    ? ElementKind::kWall
             : p.patch_class == PatchClass::kFloor ? ElementKind::kFloor
                                                   : ElementKind::kCeiling;
    out.push_back(std::move(e));
  }
  for (const auto& [name, index] : columns) {
    Element& c = out[index];
    std::vector<Eigen::Vector2d> plan;
    c.z0 = c.z1 = c.polygon.front().z();
    for (const auto& v : c.polygon) {
      plan.emplace_back(v.x(), v.y());
      c.z0 = std::min(c.z0, v.z());
      c.z1 = std::max(c.z1, v.z());
    }
    c.polygon = PlanHull(plan, c.z0);
    c.normal = Eigen::Vector3d::UnitZ();
  }
}

// The element built from SM3 patch `id` among elements [first, end): a patch's own element, or
// the column a column face belongs to. -1 when none.
int FindHost(const std::vector<Element>& elements, std::size_t first, const std::string& id) {
  for (std::size_t i = first; i < elements.size(); ++i) {
    const Json& props = elements[i].properties;
    if (props.value("patch", "") == id) return static_cast<int>(i);
    const auto faces = props.find("faces");
    if (faces != props.end() && faces->is_array() &&
        std::find(faces->begin(), faces->end(), id) != faces->end())
      return static_cast<int>(i);
  }
  return -1;
}

void AddOpenings(const ModelSet& set, std::size_t first, std::vector<Element>& out) {
  if (!set.sm4) return;
  for (const auto& o : set.sm4->openings) {
    Element e;
    e.id = set.id + "/" + o.id;
    e.room = set.id;
    const bool door = o.type == modelling::OpeningType::kDoor;
    e.class_name = door ? "door" : "window";
    e.kind = door ? ElementKind::kDoor : ElementKind::kWindow;
    for (const auto& c : o.corners) e.polygon.push_back(set.X_EM * c);
    e.host = FindHost(out, first, o.host);
    const Eigen::Vector3d nn = (e.polygon[1] - e.polygon[0]).cross(e.polygon[3] - e.polygon[0]);
    e.normal = e.host >= 0 ? out[e.host].normal : nn.normalized();
    e.width = (e.polygon[1] - e.polygon[0]).norm();
    e.height = (e.polygon[3] - e.polygon[0]).norm();
    e.properties = {{"opening", o.id}, {"host", o.host}};
    if (door) {
      e.properties["state"] = modelling::ToString(o.state);
      e.properties["opening_angle_deg"] =
          std::isfinite(o.opening_angle_deg) ? Json(o.opening_angle_deg) : Json(nullptr);
      e.properties["clear_width_m"] = o.clear_width_m;
    }
    e.properties["confidence"] = o.confidence;
    out.push_back(std::move(e));
  }
}

void AddComponents(const ModelSet& set, std::size_t first, std::vector<Element>& out) {
  if (!set.sm5) return;
  for (const auto& c : set.sm5->components) {
    Element e;
    e.id = set.id + "/" + c.id;
    e.room = set.id;
    e.class_name = c.class_name;
    e.kind = ElementKind::kComponent;
    e.centre = set.X_EM * c.centre;
    e.normal = (set.X_EM.linear() * c.normal).normalized();
    e.size = c.size;
    e.host = c.host.empty() ? -1 : FindHost(out, first, c.host);
    e.properties = {{"component", c.id},
                    {"class", c.class_name},
                    {"host", c.host},
                    {"alpha", c.alpha},
                    {"found_by", c.found_by}};
    out.push_back(std::move(e));
  }
}

void AddSet(const ModelSet& set, std::vector<Element>& out) {
  const std::size_t first = out.size();
  AddPatches(set, out);
  AddOpenings(set, first, out);
  AddComponents(set, first, out);
}

}  // namespace

const char* ToString(ElementKind kind) {
  switch (kind) {
    case ElementKind::kWall:
      return "wall";
    case ElementKind::kFloor:
      return "floor";
    case ElementKind::kCeiling:
      return "ceiling";
    case ElementKind::kColumn:
      return "column";
    case ElementKind::kDoor:
      return "door";
    case ElementKind::kWindow:
      return "window";
    case ElementKind::kComponent:
      return "component";
  }
  return "?";
}

IfcClassOf ComponentIfcClass(const std::string& c) {
  if (c.rfind("socket", 0) == 0 || c == "built_in_socket") return {"IfcOutlet", "POWEROUTLET"};
  if (c == "switch") return {"IfcSwitchingDevice", "TOGGLESWITCH"};
  if (c == "smoke_detector") return {"IfcSensor", "SMOKESENSOR"};
  if (c == "fire_alarm_switch") return {"IfcAlarm", "MANUALPULLBOX"};
  if (c == "fire_extinguisher") return {"IfcFireSuppressionTerminal", "USERDEFINED"};
  if (c == "exit_light" || c == "emergency_light") return {"IfcLightFixture", "SECURITYLIGHTING"};
  if (c == "radiator") return {"IfcSpaceHeater", "RADIATOR"};
  if (c == "electrical_panel") return {"IfcElectricDistributionBoard", "DISTRIBUTIONBOARD"};
  return {"IfcBuildingElementProxy", "USERDEFINED"};
}

BuildingModel BuildBuildingModel(const RunFolder& run) {
  BuildingModel m;
  m.name = "OpenMoPAD run";
  m.content_key = run.content_key;
  const std::string first = run.rooms.empty() ? "floor" : run.rooms.front().id;
  m.frame_note = run.floor                ? "the floor map frame (every room in one map frame)"
                 : run.placed_by_run_json ? "the map frame of room " + first +
                                                "; the other rooms placed with their run.json X_WM"
                                          : "the map frame of room " + first;
  for (const auto& room : run.rooms) {
    for (const auto& p : room.sm3.patches) {
      if (p.patch_class != PatchClass::kFloor || PolygonArea3d(p.polygon) < 1e-6) continue;
      Space s;
      s.room = room.id;
      s.footprint = PlanCcw(ToExport(room.X_EM, p.polygon));
      s.z0 = (room.X_EM * Eigen::Vector3d(0, 0, room.sm3.floor_z)).z();
      s.z1 = (room.X_EM * Eigen::Vector3d(0, 0, room.sm3.ceiling_z)).z();
      m.spaces.push_back(std::move(s));
      break;
    }
  }
  if (run.floor) {
    AddSet(*run.floor, m.elements);
    // Components stay per room unless the floor folder has its own sm5.json.
    if (!run.floor->sm5)
      for (const auto& room : run.rooms) AddComponents(room, 0, m.elements);
  } else {
    for (const auto& room : run.rooms) AddSet(room, m.elements);
  }
  return m;
}

}  // namespace mopad::exports
