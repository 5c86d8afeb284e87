#pragma once
// The object-model catalogue a simulated robot carries (the BSC models of the scene generator:
// sizes, colour and depth images, never placements; paper §3.4's database) and the SM5 colour
// recogniser trained from it alone. Built once per process on first use (thread-safe), with
// the default training params (seeded: the same weights every run).

#include "modelling/components.h"

namespace mopad::mission {

const modelling::ComponentRecogniser& RobotComponentRecogniser();

}  // namespace mopad::mission
