#include "mission/robot_catalogue.h"

#include "scenes/bsc_catalogue.h"

namespace mopad::mission {

const modelling::ComponentRecogniser& RobotComponentRecogniser() {
  static const modelling::ComponentRecogniser recogniser =
      modelling::ComponentRecogniser::Train(scenes::MakeObjectModelCatalogue());
  return recogniser;
}

}  // namespace mopad::mission
