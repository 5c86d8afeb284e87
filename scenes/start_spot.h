#pragma once
// Where the harness puts the robot (world side, from the scene's truth and geometry; never given
// to the robot as knowledge): a free-space map of the storey at the robot body's height, the
// default start of a mission, and the check of a start the user gives.
//
// Free space: a grid of `cell` m over the rooms; a cell is blocked when a triangle of the scene
// (any class: walls, door leaves, furniture, stairs, `other`) passes within half a cell diagonal
// of its centre between `ground_clearance` and `body_height` above the storey's floor, and is
// outside the building when no room polygon holds its centre. A spot is free when the robot can
// turn on it: its clearance (distance to the nearest blocked cell or the building's outline) is
// at least the footprint's half diagonal. Deterministic: a pure function of scene and truth.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/frames.h"
#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::scenes {

/// The robot body as the harness sees it (the values of sim::RobotBodyParams).
struct RobotFootprint {
  double length = 0.6;            ///< m, along base_link x, (0, 3]
  double width = 0.5;             ///< m, along base_link y, (0, 3]
  double offset_x = 0.0;          ///< m, box centre ahead of the axle centre, [-1, 1]
  double ground_clearance = 0.03; ///< m, bottom of the body above the floor
  double body_height = 1.0;       ///< m, top of the body above the floor
  /// m: the radius the robot sweeps turning on the spot (half diagonal plus the offset).
  double TurnRadius() const;
};

/// A start pose and why it was chosen (summary.json records both).
struct StartSpot {
  Pose2 X_WB;             ///< world, yaw 0 when chosen
  std::string room;       ///< truth room holding it
  std::string how;        ///< one line: "given by --start" or the reason of the choice
  double clearance = 0.0; ///< m, distance to the nearest obstacle or the building's outline
};

class FreeSpace {
 public:
  static constexpr double kCell = 0.05;  ///< m, grid pitch

  FreeSpace(const Scene& scene, const GroundTruth& truth, const RobotFootprint& robot);

  /// m: distance from `p` to the nearest blocked or outside cell (0 there).
  double Clearance(const Eigen::Vector2d& p) const;
  /// The robot can turn on `p`: inside the building with clearance >= TurnRadius().
  bool Free(const Eigen::Vector2d& p) const;
  /// "" if the footprint at X_WB touches no blocked cell and lies in the building; else what it
  /// hits: "outside the building" or "in collision with the scene (<truth id>)".
  std::string Problem(const Pose2& X_WB) const;
  /// The free cell centre nearest to `p` (ties: lower y, then lower x); false if none.
  bool NearestFree(const Eigen::Vector2d& p, Eigen::Vector2d* out) const;
  /// The free cell of room `room_id` with the largest clearance (ties: lower y, then lower x);
  /// false if the room has none. `area` (m^2) receives the room's free area when given.
  bool BestSpotIn(const std::string& room_id, Eigen::Vector2d* out, double* area = nullptr) const;

 private:
  int Index(int ix, int iy) const { return iy * nx_ + ix; }
  Eigen::Vector2d Centre(int ix, int iy) const;
  bool Cell(const Eigen::Vector2d& p, int* ix, int* iy) const;

  const GroundTruth& truth_;
  RobotFootprint robot_;
  Eigen::Vector2d origin_;  // the lower corner of cell (0, 0)
  int nx_ = 0, ny_ = 0;
  std::vector<int> room_;         // per cell: truth room index, -1 outside
  std::vector<int> blocker_;      // per cell: index into blocker_ids_, -1 free
  std::vector<std::string> blocker_ids_;
  std::vector<double> clearance_;  // m per cell
};

/// The default start of a floor mission: of the rooms that open doors (and open passages)
/// connect, the largest group; in it, of the spaces (rooms joined by open passages), the one
/// with the largest free floor times (1 + the rooms one open door away): a hall connected to
/// many rooms or a large room, never a closet or a crowded stair hall; ties: the larger, then
/// truth order. In that space the room with the most such doors, and there the free spot
/// farthest from every obstacle. Throws InputError if no room has a free spot.
StartSpot ChooseStart(const Scene& scene, const GroundTruth& truth, const RobotFootprint& robot);

/// The start in a given room (a room mission): its free spot farthest from every obstacle.
StartSpot StartInRoom(const Scene& scene, const GroundTruth& truth, const RobotFootprint& robot,
                      const std::string& room_id);

/// A start the user gave: returned with its room when the footprint is inside the building and
/// clear of the scene; else InputError "<flag> x,y,yaw: <problem>; nearest free spot x,y".
StartSpot CheckStart(const Scene& scene, const GroundTruth& truth, const RobotFootprint& robot,
                     const Pose2& X_WB, const std::string& flag = "--start");

}  // namespace mopad::scenes
