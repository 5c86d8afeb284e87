#pragma once
// The catalogue of object *models* a robot may carry (the paper's BSC database, §3.4): for each
// class its real size and a colour image and depth (protrusion) image of its visible face.
// It holds no placements: where objects are in a building is for the robot to find out.

#include <cstdint>
#include <string>
#include <vector>

namespace mopad::interfaces {

enum class Mounting { kWall, kCeiling, kFloor };

struct ObjectModel {
  std::string class_name;  ///< e.g. "socket_x2"
  Mounting mounting = Mounting::kWall;
  double width = 0.0;   ///< m, along the host surface's horizontal (u) axis
  double height = 0.0;  ///< m, along the host surface's vertical (v) axis
  double depth = 0.0;   ///< m, protrusion from the host surface (0 = flush / built-in)
  /// Class of the equipment this model marks, placed above it on the same surface (a location
  /// sign, ISO 7010: an extinguisher sign over its extinguisher); empty when it marks none.
  std::string marks;
  double pixel_size = 0.0;  ///< m per pixel of the images below
  int image_width = 0, image_height = 0;
  std::vector<std::uint8_t> colour_rgb;  ///< image_width * image_height * 3, top row first
  std::vector<float> depth_m;            ///< image_width * image_height, protrusion in m
};

struct ObjectModelCatalogue {
  std::vector<ObjectModel> models;
  const ObjectModel* Find(const std::string& class_name) const;
};

/// Writes DIR/catalogue.yaml plus one binary PPM (colour) and PFM (depth) per model.
void WriteCatalogue(const ObjectModelCatalogue& catalogue, const std::string& dir);
/// Reads what WriteCatalogue wrote; InputError on malformed files.
ObjectModelCatalogue ReadCatalogue(const std::string& dir);

}  // namespace mopad::interfaces
