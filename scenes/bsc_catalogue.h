#pragma once
// Catalogue of building service components (BSCs, the paper's §3.4 and Table 3): real
// dimensions, protruding geometry and a procedurally drawn colour texture (pictogram) for
// each class. The generator places instances; the robot may only ever get the *models*
// (MakeObjectModelCatalogue), never the placements.

#include <string>
#include <vector>

#include "interfaces/object_model_catalogue.h"
#include "scenes/scene.h"

namespace mopad::scenes {

struct BscSpec {
  std::string class_name;  ///< "socket_x2", "smoke_detector", ...
  interfaces::Mounting mounting = interfaces::Mounting::kWall;
  double width = 0.0;   ///< m, along the host's horizontal axis (ceiling: along world x)
  double height = 0.0;  ///< m, along the host's vertical axis (ceiling: along world y)
  double depth = 0.0;   ///< m, protrusion (0 for flush/built-in components)
  double default_mount_height = 0.0;  ///< m above floor (wall-mounted), for generators
  /// Class of the equipment a location sign marks, hung above it (ISO 7010; the catalogue's
  /// ObjectModel::marks); empty for none.
  std::string marks;
  // default_mount_height is the height of the model's centre (local origin), not of its lower
  // edge; it is 0 for ceiling-mounted classes. For a ceiling mount the local z axis points down
  // into the room: map the model with a proper rotation (e.g. 180° about x, so local y is
  // world -y) to keep triangle winding; the ceiling class (smoke_detector) is symmetric.
};

/// The paper's 18 classes: electrical_panel, socket_x1, socket_x2, socket_x4, built_in_socket,
/// switch, fire_extinguisher, radiator, fire_alarm_switch, smoke_detector, exit_light,
/// extinguisher_sign, fire_alarm_switch_sign, fire_sign, exit_sign, electric_sign,
/// emergency_light, door_sign.
const std::vector<BscSpec>& BscCatalogue();
/// nullptr if unknown.
const BscSpec* FindBsc(const std::string& class_name);

/// Geometry of one instance in its local frame: x along the host's horizontal axis (width),
/// y along its vertical axis (height), z out of the host surface (z = 0 on the surface);
/// centred on x = y = 0. Parts carry element_class kServiceComponent and subclass = class name;
/// material/texture indices refer to the returned Scene's own lists.
Scene BuildBscModel(const std::string& class_name);

/// The robot-side model of a class: size plus colour and depth images of its front face
/// rendered orthographically from BuildBscModel at `pixel_size` metres per pixel.
interfaces::ObjectModel MakeObjectModel(const std::string& class_name, double pixel_size = 0.002);
interfaces::ObjectModelCatalogue MakeObjectModelCatalogue(double pixel_size = 0.002);

}  // namespace mopad::scenes
