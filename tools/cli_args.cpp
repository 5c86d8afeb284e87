#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/error.h"
#include "tools/commands.h"

namespace mopad::tools {

Pose2 ParsePoseArg(const std::string& opt, const std::string& text) {
  std::stringstream ss(text);
  std::string item;
  std::vector<double> v;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError(opt + ": error: bad number; got '" + text + "', expected x,y,yaw_deg");
    }
  }
  if (v.size() != 3)
    throw InputError(opt + ": error: wrong count; got '" + text + "', expected x,y,yaw_deg");
  for (double x : v)
    if (!std::isfinite(x))
      throw InputError(opt + ": error: not a finite number; got '" + text +
                       "', expected x,y,yaw_deg in metres and degrees");
  return Pose2{v[0], v[1], DegToRad(v[2])};
}

}  // namespace mopad::tools
