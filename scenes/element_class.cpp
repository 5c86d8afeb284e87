#include "scenes/element_class.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace mopad::scenes {
namespace {

constexpr std::array<std::pair<ElementClass, std::string_view>, 22> kNames{{
    {ElementClass::kUnknown, "unknown"},
    {ElementClass::kWall, "wall"},
    {ElementClass::kFloor, "floor"},
    {ElementClass::kCeiling, "ceiling"},
    {ElementClass::kColumn, "column"},
    {ElementClass::kDoorFrame, "door_frame"},
    {ElementClass::kDoorLeaf, "door_leaf"},
    {ElementClass::kWindowFrame, "window_frame"},
    {ElementClass::kWindowGlass, "window_glass"},
    {ElementClass::kServiceComponent, "service_component"},
    {ElementClass::kFurniture, "furniture"},
    {ElementClass::kClutter, "clutter"},
    {ElementClass::kBeam, "beam"},
    {ElementClass::kSlab, "slab"},
    {ElementClass::kRoof, "roof"},
    {ElementClass::kStair, "stair"},
    {ElementClass::kRailing, "railing"},
    {ElementClass::kSite, "site"},
    {ElementClass::kSpace, "space"},
    {ElementClass::kOther, "other"},
    {ElementClass::kPerson, "person"},
    {ElementClass::kUnknown, "unknown"},
}};

std::string Lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace

std::string_view ToString(ElementClass c) {
  for (const auto& [cls, name] : kNames)
    if (cls == c) return name;
  return "unknown";
}

bool ParseElementClass(std::string_view name, ElementClass* out) {
  for (const auto& [cls, n] : kNames) {
    if (n == name) {
      *out = cls;
      return true;
    }
  }
  return false;
}

bool IsStructural(ElementClass c) {
  return c == ElementClass::kWall || c == ElementClass::kFloor || c == ElementClass::kCeiling ||
         c == ElementClass::kColumn;
}

ElementClass FromIfcClass(std::string_view ifc_class) {
  const std::string c = Lower(ifc_class);
  // Longest prefixes first where one name is a prefix of another (ifcwallstandardcase).
  if (c.rfind("ifcwall", 0) == 0 || c == "ifccurtainwall") return ElementClass::kWall;
  if (c == "ifccolumn" || c == "ifccolumnstandardcase") return ElementClass::kColumn;
  if (c == "ifcdoor" || c == "ifcdoorstandardcase") return ElementClass::kDoorLeaf;
  if (c == "ifcwindow" || c == "ifcwindowstandardcase") return ElementClass::kWindowFrame;
  if (c == "ifcslab" || c == "ifcslabstandardcase") return ElementClass::kSlab;
  if (c == "ifccovering") return ElementClass::kCeiling;
  if (c == "ifcbeam" || c == "ifcbeamstandardcase") return ElementClass::kBeam;
  if (c == "ifcroof") return ElementClass::kRoof;
  if (c == "ifcstair" || c == "ifcstairflight" || c == "ifcramp" || c == "ifcrampflight")
    return ElementClass::kStair;
  if (c == "ifcrailing") return ElementClass::kRailing;
  if (c == "ifcsite") return ElementClass::kSite;
  if (c == "ifcspace") return ElementClass::kSpace;
  if (c == "ifcfurnishingelement" || c == "ifcfurniture") return ElementClass::kFurniture;
  if (c.rfind("ifcflow", 0) == 0 || c.rfind("ifcdistribution", 0) == 0 ||
      c == "ifcenergyconversiondevice")
    return ElementClass::kServiceComponent;
  if (c.rfind("ifc", 0) == 0) return ElementClass::kOther;
  return ElementClass::kUnknown;
}

}  // namespace mopad::scenes
