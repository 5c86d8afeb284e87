// Service components and furniture of a BIM import: the catalogue class of a component, its
// host (the nearest wall face or ceiling within component_snap, onto which it is moved) and a
// furniture item's yawed box (scenes/bim_import_internal.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "common/frames.h"
#include "scenes/bim_import_internal.h"

namespace mopad::scenes::bim {

namespace {

// The catalogue class that the words of a component's names say ("" = none), in the order that
// keeps compound names right: a "Thermostat" or "Lichtschalter" is no light, a "switchboard" no
// switch. English and German, the languages of the files at hand; ASCII lower case, so
// "Heizk\xc3\xb6rper" matches by its ASCII stem.
std::string ClassFromWords(const std::string& names, const Eigen::Vector3d& size) {
  auto has = [&](std::initializer_list<const char*> words) {
    for (const char* w : words)
      if (names.find(w) != std::string::npos) return true;
    return false;
  };
  const double w = std::max(size.x(), size.y());
  const std::string socket = w < 0.12 ? "socket_x1" : w < 0.22 ? "socket_x2" : "socket_x4";
  if (has({"thermostat", "temperaturregler", "temperature control"})) return "other";
  if (has({"smoke", "rauchmelder", "rauchwarnmelder"})) return "smoke_detector";
  if (has({"call point", "druckknopfmelder", "handfeuermelder", "fire alarm", "feuermelder"}))
    return "fire_alarm_switch";
  if (has({"extinguisher", "feuerl"})) return "fire_extinguisher";
  if (has({"distribution board", "switchboard", "panelboard", "electrical panel",
           "unterverteil", "verteiler"}))
    return "electrical_panel";
  if (has({"switch", "schalter", "dimmer", "taster"})) return "switch";
  if (has({"receptacle", "outlet", "socket", "steckdose"})) return socket;
  if (has({"radiator", "heizk", "heater"})) return "radiator";
  if (has({"exit", "notausgang", "fluchtweg"})) return "exit_light";
  if (has({"emergency light", "notleuchte", "sicherheitsleuchte", "notbeleuchtung"}))
    return "emergency_light";
  if (has({"light", "lamp", "leuchte", "luminaire"})) return "other";
  return "";
}

}  // namespace

std::string ComponentClass(const std::string& ifc, const std::string& type_class,
                           const Eigen::Vector3d& size, const std::string& names) {
  // IFC 2x3 has no IfcOutlet or IfcSwitchingDevice: a generic IfcFlowTerminal/IfcFlowController
  // says what it is through its type object (IfcOutletType -> "ifcoutlet").
  const std::string c = type_class.empty() ? Lower(ifc) : type_class;
  const std::string words = ClassFromWords(Lower(names), size);
  const std::string other = "other:" + ifc;
  if (c == "ifcoutlet") {
    const double w = std::max(size.x(), size.y());
    return w < 0.12 ? "socket_x1" : w < 0.22 ? "socket_x2" : "socket_x4";
  }
  if (c == "ifcswitchingdevice") return "switch";
  if (c == "ifcalarm") return "fire_alarm_switch";
  if (c == "ifcelectricdistributionpoint" || c == "ifcelectricdistributionboard")
    return "electrical_panel";
  if (c == "ifcspaceheater") return "radiator";
  // A sensor is a smoke detector unless its name says otherwise (a thermostat); kept only when
  // ceiling-mounted (HostComponent).
  if (c == "ifcsensor") return words.empty() ? "smoke_detector" : words == "other" ? other : words;
  if (!type_class.empty() && c != Lower(ifc)) return ComponentClass(ifc, "", size, names);
  // Generic classes: the names decide.
  if (!words.empty() && words != "other") return words;
  return other;
}

void Importer::Components() {
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
void Importer::Yawed(const Element& e, FurnitureItem* fi) const {
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

bool Importer::HostComponent(std::size_t ei, std::map<std::string, int>* counts) {
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
    if (inside && std::abs(d) <= p_.component_snap && std::abs(d) < best && r < ceilings_.size() &&
        !ceilings_[r].polygons.empty()) {
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
  const std::string guid = NodeGuid(e.node);
  const auto type_guid = type_guid_.find(guid);
  const auto type_name =
      type_guid == type_guid_.end() ? names_.end() : names_.find(type_guid->second);
  const std::string names = NiceNameOnly(e.node) + " | " + NodeLabel(e.node) + " | " +
                            (type_name == names_.end() ? std::string() : type_name->second);
  std::string cls =
      ComponentClass(e.ifc, type == type_class_.end() ? "" : type->second, e.box.sizes(), names);
  // Where the catalogue says a class mounts, or the component is not a catalogue class.
  const bool ceiling_class = cls == "smoke_detector";
  if (cls.rfind("other:", 0) != 0 && ceiling_class != ceiling) cls = "other:" + e.ifc;
  s.bsc_class = cls;
  // One counter per id prefix: ids stay unique whatever classes, and models, they come from.
  const std::string prefix = cls.rfind("other:", 0) == 0 ? "other" : cls;
  s.id = prefix + "_" + std::to_string(++(*counts)[prefix]);
  if (!guid.empty()) out_.component_guids[s.id] = guid;
  s.host = host->id;
  s.room = host->rooms.empty() ? "" : host->rooms[0];
  for (std::size_t pi : e.parts) {
    const MeshPart& part = scene_.parts[pi];
    Bucket& b = out_bucket_.Get(s.id, ElementClass::kServiceComponent, cls, s.room, part.material);
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

}  // namespace mopad::scenes::bim
