#include "scenes/scene_summary.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace mopad::scenes {

SceneSummary Summarise(const scenes::Scene& scene, const scenes::GroundTruth* truth,
                       const std::string& path) {
  SceneSummary s;
  s.path = path;
  s.parts = scene.parts.size();
  s.triangles = scene.TriangleCount();
  s.materials = scene.materials.size();
  s.textures = scene.textures.size();
  s.bounds = scene.Bounds();
  std::map<std::string, std::set<std::string>> ids;
  for (const auto& p : scene.parts) {
    const std::string cls(scenes::ToString(p.element_class));
    auto& c = s.per_class[cls];
    c.triangles += p.triangles.size();
    if (p.element_id.empty())
      ++c.elements;
    else
      ids[cls].insert(p.element_id);
  }
  for (const auto& [cls, set] : ids) s.per_class[cls].elements += set.size();

  if (truth) {
    s.has_truth = true;
    s.rooms = truth->rooms.size();
    for (const auto& e : truth->elements) {
      switch (e.element_class) {
        case scenes::ElementClass::kWall:
          ++s.walls;
          break;
        case scenes::ElementClass::kFloor:
          ++s.floors;
          break;
        case scenes::ElementClass::kCeiling:
          ++s.ceilings;
          break;
        case scenes::ElementClass::kColumn:
          ++s.columns;
          break;
        default:
          break;
      }
    }
    for (const auto& o : truth->openings) {
      if (o.type == scenes::OpeningType::kWindow) {
        ++s.windows;
        continue;
      }
      ++s.doors;
      switch (o.state) {
        case scenes::DoorState::kOpen:
          ++s.doors_open;
          break;
        case scenes::DoorState::kSemiOpen:
          ++s.doors_semi_open;
          break;
        case scenes::DoorState::kClosed:
          ++s.doors_closed;
          break;
      }
    }
    for (const auto& b : truth->service_components) ++s.bsc_per_class[b.bsc_class];
    s.bsc_total = truth->service_components.size();
    s.furniture = truth->furniture.size();
    s.connections = truth->connections.size();
  }
  return s;
}

std::string FormatSceneSummary(const SceneSummary& s) {
  std::ostringstream o;
  char buf[256];
  o << "scene: " << s.path << "\n";
  std::snprintf(buf, sizeof buf, "triangles: %zu  parts: %zu  materials: %zu  textures: %zu\n",
                s.triangles, s.parts, s.materials, s.textures);
  o << buf;
  if (!s.bounds.isEmpty()) {
    const auto& a = s.bounds.min();
    const auto& b = s.bounds.max();
    std::snprintf(buf, sizeof buf,
                  "bounds (m, Z-up): x [%.3f, %.3f]  y [%.3f, %.3f]  z [%.3f, %.3f]  size %.3f x "
                  "%.3f x %.3f\n",
                  a.x(), b.x(), a.y(), b.y(), a.z(), b.z(), b.x() - a.x(), b.y() - a.y(),
                  b.z() - a.z());
    o << buf;
  }
  o << "\nclass                 elements   triangles\n";
  for (const auto& [cls, c] : s.per_class) {
    std::snprintf(buf, sizeof buf, "%-20s %9zu %11zu\n", cls.c_str(), c.elements, c.triangles);
    o << buf;
  }
  if (s.has_truth) {
    std::snprintf(buf, sizeof buf,
                  "\ntruth: %zu rooms, %zu walls, %zu floors, %zu ceilings, %zu columns\n"
                  "       %zu doors (%zu open, %zu semi-open, %zu closed), %zu windows, "
                  "%zu furniture, %zu door connections\n"
                  "       %zu service components:\n",
                  s.rooms, s.walls, s.floors, s.ceilings, s.columns, s.doors, s.doors_open,
                  s.doors_semi_open, s.doors_closed, s.windows, s.furniture, s.connections,
                  s.bsc_total);
    o << buf;
    for (const auto& [cls, n] : s.bsc_per_class) {
      std::snprintf(buf, sizeof buf, "         %-24s %4zu\n", cls.c_str(), n);
      o << buf;
    }
  }
  std::string out = o.str();
  if (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

std::string SceneSummaryJson(const SceneSummary& s) {
  nlohmann::ordered_json j;
  j["path"] = s.path;
  j["triangles"] = s.triangles;
  j["parts"] = s.parts;
  j["materials"] = s.materials;
  j["textures"] = s.textures;
  if (!s.bounds.isEmpty()) {
    j["bounds"] = {{"min", {s.bounds.min().x(), s.bounds.min().y(), s.bounds.min().z()}},
                   {"max", {s.bounds.max().x(), s.bounds.max().y(), s.bounds.max().z()}}};
  }
  for (const auto& [cls, c] : s.per_class)
    j["classes"][cls] = {{"elements", c.elements}, {"triangles", c.triangles}};
  if (s.has_truth) {
    auto& t = j["truth"];
    t["rooms"] = s.rooms;
    t["walls"] = s.walls;
    t["floors"] = s.floors;
    t["ceilings"] = s.ceilings;
    t["columns"] = s.columns;
    t["doors"] = {{"total", s.doors},
                  {scenes::ToString(scenes::DoorState::kOpen), s.doors_open},
                  {scenes::ToString(scenes::DoorState::kSemiOpen), s.doors_semi_open},
                  {scenes::ToString(scenes::DoorState::kClosed), s.doors_closed}};
    t["windows"] = s.windows;
    t["furniture"] = s.furniture;
    t["connections"] = s.connections;
    t["service_components"]["total"] = s.bsc_total;
    for (const auto& [cls, n] : s.bsc_per_class) t["service_components"]["per_class"][cls] = n;
  }
  return j.dump(2);
}

}  // namespace mopad::scenes
