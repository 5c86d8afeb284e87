#pragma once
// People walking through the rooms of a floor during a mission: moving occluders for the TLS
// and both LRFs (EmbreeWorld movers), never part of the truth of the building. World side: it
// reads the truth's rooms and the robot's true position; the robot only sees them in its
// sensors.
//
// Each person is a simple body (two legs, a torso, a head; 1.60-1.90 m tall, 0.45 m across the
// shoulders) in clothes of their own colours, and walks in one room: to a free spot drawn at
// random that a straight walk reaches, stands there a while (exponential, mean `pause_mean`),
// and walks on, turning at most kTurnRate. Free spots are the room's floor that a vertical ray
// from the ceiling reaches without touching furniture or anything else, `kRadius` clear of all
// of it.
// People give way to the robot: a person does not step closer than `clearance` to the robot's
// centre; whoever would, walking or standing, turns to a spot away from it (or stands, when
// there is none).
//
// Frames and units: world frame W (Z-up), metres, seconds, radians. Deterministic: the same
// world, truth, params, seed and robot positions at each step give the same walks.

#include <cstdint>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "common/rng.h"
#include "scenes/ground_truth.h"
#include "sim/embree_world.h"

namespace mopad::sim {

struct PeopleParams {
  int count = 0;            ///< people on the floor, [0, 50]; 0: nobody
  double speed = 1.2;       ///< m/s, mean walking speed (each person within +-20 %), [0.3, 2.5]
  double pause_mean = 4.0;  ///< s, mean standing time at each spot, [0, 600]
  double clearance = 1.0;   ///< m, robot centre to a person's centre a person keeps, [0.3, 5]
  std::uint64_t seed = 0;   ///< the people's own draws; 0 in a profile = the run's seed

  template <class V>
  void Visit(V& v) {
    v("count", count, Bounds{0, 50});
    v("speed", speed, Bounds{0.3, 2.5});
    v("pause_mean", pause_mean, Bounds{0, 600});
    v("clearance", clearance, Bounds{0.3, 5});
    v("seed", seed);
  }
  bool Enabled() const { return count > 0; }
};

class People {
 public:
  static constexpr double kRadius = 0.3;    ///< m, a person's clearance from anything solid
  static constexpr double kTurnRate = 4.0;  ///< rad/s
  static constexpr double kCell = 0.1;      ///< m, the free-spot grid

  /// People in the rooms of `truth` with enough free floor, drawn from `seed`, none within
  /// 2 m of `start` (the robot's start, world). Reads `world` (which must not have its movers
  /// yet). InputError when `params` are out of range; a floor without free rooms gets nobody.
  People(const EmbreeWorld& world, const scenes::GroundTruth& truth, const PeopleParams& params,
         std::uint64_t seed, const Vec2& start);

  std::size_t size() const { return people_.size(); }
  /// Each person's body as a mover (id "person_<k>", parts of class kPerson in the person's
  /// frame), for EmbreeWorld::AddMovers.
  std::vector<MoverModel> Models() const;
  /// Where everybody is now.
  std::vector<MoverPose> Poses() const;
  /// The room each person walks in (truth id).
  const std::string& RoomOf(std::size_t i) const { return people_[i].room; }

  /// Advances everybody by `dt` (s) with the robot's centre at `robot` (world).
  void Step(double dt, const Vec2& robot);
  /// The track over the next `duration` s (robot standing at `robot`), stepped at `dt` from
  /// now as Step would, sampled at `knots` evenly spaced times (the first: now), for
  /// EmbreeWorld::SetMoverTrack. Leaves this unchanged.
  std::vector<std::vector<MoverPose>> Track(double duration, double dt, int knots,
                                            const Vec2& robot) const;

 private:
  struct Room {
    std::string id;
    Vec2 origin = Vec2::Zero();  ///< the grid's corner
    int nx = 0, ny = 0;
    std::vector<std::uint8_t> free;  ///< nx * ny cells, 1 = a free spot
    std::vector<int> spots;          ///< indices of the free cells
    Vec2 Centre(int cell) const;
    bool Free(const Vec2& p) const;
    bool Walkable(const Vec2& a, const Vec2& b) const;
  };
  struct Person {
    std::string room;
    int room_index = 0;
    Vec2 p = Vec2::Zero(), goal = Vec2::Zero();
    double yaw = 0.0, speed = 1.2, pause = 0.0;
    double height = 1.75;
    CounterRng rng{0};           ///< the person's own stream of draws
    int colours[3] = {0, 0, 0};  ///< palette indices: trousers, top, skin
  };
  double Draw(Person& person) const;  ///< the person's next uniform in [0, 1)
  void NextGoal(Person& person, const Vec2& robot) const;
  void StepPerson(Person& person, double dt, const Vec2& robot) const;

  PeopleParams params_;
  std::vector<Room> rooms_;
  std::vector<Person> people_;
};

}  // namespace mopad::sim
