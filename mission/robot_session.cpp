#include "mission/robot_session.h"

namespace mopad::mission {

RobotSession::RobotSession(const sim::EmbreeWorld& world, const DriveParams& params,
                           const Pose2& X_WB_start, const FaultParams& faults,
                           const std::optional<DoorFaultWorld>& door,
                           const sim::RealismParams& realism,
                           const std::optional<PeopleWorld>& people)
    : params_(params),
      world_robot_(world, params, X_WB_start, params.seed, faults, door, realism, people),
      navigator_(world_robot_, params.navigator, params.seed) {}

DriveStatus RobotSession::NavigateTo(const Pose2& goal_M, std::string* message) {
  const DriveStatus s = navigator_.NavigateTo(goal_M);
  if (message) *message = navigator_.Log().message;
  return s;
}

DriveResult RobotSession::Result() const {
  DriveResult res;
  static_cast<autonomy::NavigatorLog&>(res) = navigator_.Log();
  res.map = navigator_.Map();
  world_robot_.FillResult(res);
  return res;
}

}  // namespace mopad::mission
