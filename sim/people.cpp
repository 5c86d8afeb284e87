#include "sim/people.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.h"
#include "common/polygon.h"
#include "common/rng.h"

namespace mopad::sim {

namespace {

// Clothes and skin (linear RGB) and their reflectance at the scanner's 1550 nm: dyed cotton and
// synthetics are bright there whatever their visible colour (most dyes are transparent in the
// near infrared), skin is dark (water absorbs at 1550 nm).
struct Cloth {
  float r, g, b;
};
constexpr Cloth kTrousers[] = {
    {0.05f, 0.06f, 0.12f}, {0.03f, 0.03f, 0.03f}, {0.20f, 0.19f, 0.17f}, {0.40f, 0.33f, 0.22f}};
constexpr Cloth kTops[] = {{0.80f, 0.80f, 0.78f}, {0.08f, 0.15f, 0.40f}, {0.45f, 0.05f, 0.05f},
                           {0.10f, 0.25f, 0.10f}, {0.20f, 0.20f, 0.20f}, {0.85f, 0.65f, 0.15f}};
constexpr Cloth kSkin[] = {{0.65f, 0.45f, 0.35f}, {0.40f, 0.25f, 0.17f}, {0.20f, 0.11f, 0.07f}};
constexpr float kClothNir = 0.45f, kSkinNir = 0.12f;

// An upright elliptic prism (n sides, caps) from z0 to z1 at (cx, cy) with semi-axes (ax, ay).
void AddPrism(scenes::MeshPart& part, double cx, double cy, double ax, double ay, double z0,
              double z1, int n = 10) {
  const int base = static_cast<int>(part.positions.size());
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    const float x = static_cast<float>(cx + ax * std::cos(a));
    const float y = static_cast<float>(cy + ay * std::sin(a));
    part.positions.emplace_back(x, y, static_cast<float>(z0));
    part.positions.emplace_back(x, y, static_cast<float>(z1));
  }
  for (int k = 0; k < n; ++k) {
    const int a0 = base + 2 * k, a1 = a0 + 1, b0 = base + 2 * ((k + 1) % n), b1 = b0 + 1;
    part.triangles.emplace_back(a0, b0, b1);  // outward
    part.triangles.emplace_back(a0, b1, a1);
  }
  for (int k = 1; k + 1 < n; ++k) {
    part.triangles.emplace_back(base, base + 2 * (k + 1), base + 2 * k);              // bottom
    part.triangles.emplace_back(base + 1, base + 2 * k + 1, base + 2 * (k + 1) + 1);  // top
  }
}

scenes::MeshPart NewPart(const std::string& id, const std::string& name, int material) {
  scenes::MeshPart p;
  p.name = id + "/" + name;
  p.element_id = id;
  p.element_class = scenes::ElementClass::kPerson;
  p.subclass = "person";
  p.material = material;
  return p;
}

scenes::Material ClothMaterial(const std::string& name, const Cloth& c, float nir) {
  scenes::Material m;
  m.name = name;
  m.base_color = Eigen::Vector4f(c.r, c.g, c.b, 1.0f);
  m.roughness = 1.0f;
  m.nir_reflectance = nir;
  return m;
}

double Wrap(double a) { return std::remainder(a, 2.0 * kPi); }

// Keeps the largest 4-connected set of cells of `cells` (nx * ny, 1 = in); the first in cell
// order among equals.
void KeepLargestPart(int nx, int ny, std::vector<std::uint8_t>& cells) {
  std::vector<int> label(cells.size(), -1), stack;
  int best = -1;
  std::size_t best_size = 0;
  for (int start = 0; start < nx * ny; ++start) {
    if (!cells[static_cast<std::size_t>(start)] || label[static_cast<std::size_t>(start)] >= 0)
      continue;
    std::size_t size = 0;
    stack.assign(1, start);
    label[static_cast<std::size_t>(start)] = start;
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      ++size;
      const int x = c % nx, y = c / nx;
      const int next[4][2] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
      for (const auto& n : next) {
        if (n[0] < 0 || n[1] < 0 || n[0] >= nx || n[1] >= ny) continue;
        const auto k = static_cast<std::size_t>(n[1] * nx + n[0]);
        if (!cells[k] || label[k] >= 0) continue;
        label[k] = start;
        stack.push_back(n[1] * nx + n[0]);
      }
    }
    if (size > best_size) best = start, best_size = size;
  }
  for (std::size_t k = 0; k < cells.size(); ++k) cells[k] = label[k] == best && best >= 0;
}

}  // namespace

Vec2 People::Room::Centre(int cell) const {
  return origin + kCell * Vec2((cell % nx) + 0.5, (cell / nx) + 0.5);
}

bool People::Room::Free(const Vec2& p) const {
  const Vec2 q = (p - origin) / kCell;
  const int ix = static_cast<int>(std::floor(q.x())), iy = static_cast<int>(std::floor(q.y()));
  return ix >= 0 && iy >= 0 && ix < nx && iy < ny && free[static_cast<std::size_t>(iy * nx + ix)];
}

bool People::Room::Walkable(const Vec2& a, const Vec2& b) const {
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * kCell))));
  for (int k = 0; k <= n; ++k)
    if (!Free(a + (b - a) * (static_cast<double>(k) / n))) return false;
  return true;
}

People::People(const EmbreeWorld& world, const scenes::GroundTruth& truth,
               const PeopleParams& params, std::uint64_t seed, const Vec2& start)
    : params_(params) {
  ValidateParams(params_, "realism.people.");
  if (world.MoverCount() > 0) throw std::logic_error("People: the world has movers already");
  if (!params_.Enabled()) return;
  // Free spots per room: cells whose floor a vertical ray from just under the ceiling reaches
  // and with no surface within a cell of their centre at four heights up to 1.6 m (so a thin
  // door leaf is seen too); then eroded by kRadius, and only the largest connected part (not
  // the inside of a column or a tall cabinet).
  for (const scenes::Room& r : truth.rooms) {
    if (r.polygon.size() < 3) continue;
    Vec2 lo = r.polygon.front(), hi = lo;
    for (const Vec2& q : r.polygon) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    Room room;
    room.id = r.id;
    room.origin = lo;
    room.nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / kCell));
    room.ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / kCell));
    if (room.nx <= 0 || room.ny <= 0 || room.nx * room.ny > 4000000) continue;
    std::vector<std::uint8_t> floor(static_cast<std::size_t>(room.nx) * room.ny, 0);
    const double top = r.ceiling_z - 0.02;
    std::vector<Eigen::Vector3f> origins, dirs;
    std::vector<RayHit> hits;
    for (int c = 0; c < room.nx * room.ny; ++c) {
      const Vec2 q = room.Centre(c);
      if (!PointInPolygon(q, r.polygon)) continue;
      const float x = static_cast<float>(q.x()), y = static_cast<float>(q.y());
      const RayHit h = world.Intersect(Eigen::Vector3f(x, y, static_cast<float>(top)),
                                       -Eigen::Vector3f::UnitZ());
      if (!h.hit()) continue;
      const auto cls = world.Part(h.part).element_class;
      if (cls != scenes::ElementClass::kFloor && cls != scenes::ElementClass::kSlab) continue;
      if (top - h.t >= r.floor_z + 0.1) continue;
      origins.clear();
      dirs.clear();
      for (double z : {0.15, 0.6, 1.1, 1.6})
        for (int k = 0; k < 8; ++k) {
          origins.emplace_back(x, y, static_cast<float>(std::min(r.floor_z + z, top)));
          dirs.emplace_back(static_cast<float>(std::cos(k * kPi / 4)),
                            static_cast<float>(std::sin(k * kPi / 4)), 0.0f);
        }
      hits.assign(origins.size(), RayHit{});
      world.IntersectMany(origins, dirs, 0.0f, static_cast<float>(kCell), hits);
      bool clear = true;
      for (const RayHit& hk : hits) clear = clear && !hk.hit();
      floor[static_cast<std::size_t>(c)] = clear ? 1 : 0;
    }
    const int reach = static_cast<int>(std::ceil(kRadius / kCell));
    room.free.assign(floor.size(), 0);
    for (int iy = 0; iy < room.ny; ++iy)
      for (int ix = 0; ix < room.nx; ++ix) {
        bool ok = floor[static_cast<std::size_t>(iy * room.nx + ix)] != 0;
        for (int dy = -reach; ok && dy <= reach; ++dy)
          for (int dx = -reach; ok && dx <= reach; ++dx) {
            if ((dx * dx + dy * dy) * kCell * kCell > kRadius * kRadius) continue;
            const int x = ix + dx, y = iy + dy;
            ok = x >= 0 && y >= 0 && x < room.nx && y < room.ny &&
                 floor[static_cast<std::size_t>(y * room.nx + x)] != 0;
          }
        if (ok) room.free[static_cast<std::size_t>(iy * room.nx + ix)] = 1;
      }
    KeepLargestPart(room.nx, room.ny, room.free);
    for (int c = 0; c < room.nx * room.ny; ++c)
      if (room.free[static_cast<std::size_t>(c)]) room.spots.push_back(c);
    // A room a person can walk in: 2 m^2 of free spots.
    if (static_cast<double>(room.spots.size()) * kCell * kCell >= 2.0) rooms_.push_back(room);
  }
  if (rooms_.empty()) return;
  // Rooms in a drawn order; person k walks in room k mod rooms.
  CounterRng order(seed, "sim/people/rooms");
  std::vector<int> room_order(rooms_.size());
  for (std::size_t i = 0; i < room_order.size(); ++i) room_order[i] = static_cast<int>(i);
  for (std::size_t i = room_order.size(); i > 1; --i)
    std::swap(room_order[i - 1], room_order[order.Below(i)]);
  for (int k = 0; k < params_.count; ++k) {
    Person person;
    person.room_index = room_order[static_cast<std::size_t>(k) % room_order.size()];
    const Room& room = rooms_[static_cast<std::size_t>(person.room_index)];
    person.room = room.id;
    person.rng = CounterRng(seed, "sim/people/person", static_cast<std::uint64_t>(k));
    person.speed = params_.speed * (0.8 + 0.4 * Draw(person));
    person.height = 1.60 + 0.30 * Draw(person);
    person.colours[0] = static_cast<int>(Draw(person) * std::size(kTrousers));
    person.colours[1] = static_cast<int>(Draw(person) * std::size(kTops));
    person.colours[2] = static_cast<int>(Draw(person) * std::size(kSkin));
    // A start spot 2 m from the robot's start (the room's first such spot after a drawn one).
    const std::size_t n = room.spots.size();
    const std::size_t first = static_cast<std::size_t>(Draw(person) * static_cast<double>(n));
    person.p = room.Centre(room.spots[first]);
    for (std::size_t j = 0; j < n; ++j) {
      const Vec2 q = room.Centre(room.spots[(first + j) % n]);
      if ((q - start).norm() >= 2.0) {
        person.p = q;
        break;
      }
    }
    person.goal = person.p;
    person.yaw = 2.0 * kPi * Draw(person);
    person.pause = -params_.pause_mean * std::log(1.0 - Draw(person));
    people_.push_back(person);
  }
}

double People::Draw(Person& person) const { return person.rng.Uniform(); }

std::vector<MoverModel> People::Models() const {
  std::vector<MoverModel> out;
  for (std::size_t k = 0; k < people_.size(); ++k) {
    const Person& p = people_[k];
    MoverModel m;
    m.id = "person_" + std::to_string(k + 1);
    m.materials = {ClothMaterial(m.id + "/trousers", kTrousers[p.colours[0]], kClothNir),
                   ClothMaterial(m.id + "/top", kTops[p.colours[1]], kClothNir),
                   ClothMaterial(m.id + "/skin", kSkin[p.colours[2]], kSkinNir)};
    const double h = p.height;
    scenes::MeshPart legs = NewPart(m.id, "legs", 0);
    AddPrism(legs, 0.0, 0.10, 0.075, 0.075, 0.0, 0.47 * h, 8);
    AddPrism(legs, 0.0, -0.10, 0.075, 0.075, 0.0, 0.47 * h, 8);
    scenes::MeshPart top = NewPart(m.id, "top", 1);
    AddPrism(top, 0.0, 0.0, 0.13, 0.20, 0.47 * h, 0.82 * h);
    AddPrism(top, 0.0, 0.25, 0.05, 0.05, 0.45 * h, 0.81 * h, 6);  // arms
    AddPrism(top, 0.0, -0.25, 0.05, 0.05, 0.45 * h, 0.81 * h, 6);
    scenes::MeshPart skin = NewPart(m.id, "head", 2);
    AddPrism(skin, 0.0, 0.0, 0.05, 0.05, 0.82 * h, 0.87 * h, 6);  // neck
    AddPrism(skin, 0.01, 0.0, 0.10, 0.08, 0.87 * h, h);
    m.parts = {std::move(legs), std::move(top), std::move(skin)};
    out.push_back(std::move(m));
  }
  return out;
}

std::vector<MoverPose> People::Poses() const {
  std::vector<MoverPose> out;
  for (const Person& p : people_) out.push_back({p.p.x(), p.p.y(), p.yaw});
  return out;
}

void People::NextGoal(Person& person, const Vec2& robot) const {
  const Room& room = rooms_[static_cast<std::size_t>(person.room_index)];
  const double away = (person.p - robot).norm();
  for (int attempt = 0; attempt < 40; ++attempt) {
    const std::size_t i = static_cast<std::size_t>(Draw(person) * room.spots.size());
    const Vec2 q = room.Centre(room.spots[std::min(i, room.spots.size() - 1)]);
    if ((q - person.p).norm() < 1.0) continue;
    // Not to where the robot is, and away from it while it is near.
    if ((q - robot).norm() < params_.clearance + 0.5) continue;
    if (away < params_.clearance + 0.5 && (q - robot).norm() < away) continue;
    if (!room.Walkable(person.p, q)) continue;
    person.goal = q;
    return;
  }
  person.goal = person.p;  // nowhere to go now: stand a while
  person.pause = std::max(person.pause, 1.0);
}

void People::StepPerson(Person& person, double dt, const Vec2& robot) const {
  const double to_robot = (person.p - robot).norm();
  if (person.pause > 0.0) {
    person.pause -= dt;
    // A standing person steps aside from a robot that comes close.
    if (person.pause <= 0.0 || to_robot < params_.clearance) {
      person.pause = 0.0;
      NextGoal(person, robot);
    }
    return;
  }
  const Vec2 d = person.goal - person.p;
  const double dist = d.norm();
  if (dist < 1e-3) {
    person.pause = -params_.pause_mean * std::log(1.0 - Draw(person));
    if (!(person.pause > 0.0)) NextGoal(person, robot);
    return;
  }
  const double heading = std::atan2(d.y(), d.x());
  const double turn = Wrap(heading - person.yaw);
  const double max_turn = kTurnRate * dt;
  person.yaw = Wrap(person.yaw + std::clamp(turn, -max_turn, max_turn));
  if (std::abs(turn) > 0.5) return;  // turning on the spot first
  const Vec2 next = person.p + d * (std::min(person.speed * dt, dist) / dist);
  if ((next - robot).norm() < params_.clearance && (next - robot).norm() < to_robot) {
    NextGoal(person, robot);  // step aside: somewhere away from the robot, or stand
    return;
  }
  person.p = next;
}

void People::Step(double dt, const Vec2& robot) {
  for (Person& p : people_) StepPerson(p, dt, robot);
}

std::vector<std::vector<MoverPose>> People::Track(double duration, double dt, int knots,
                                                  const Vec2& robot) const {
  std::vector<std::vector<MoverPose>> out(people_.size());
  if (knots < 1) return out;
  People copy = *this;
  std::vector<MoverPose> a = copy.Poses(), b = a;
  double ta = 0.0, tb = 0.0;
  for (int k = 0; k < knots; ++k) {
    const double tk = knots == 1 ? 0.0 : duration * k / (knots - 1);
    while (tb < tk - 1e-9) {
      a = b;
      ta = tb;
      copy.Step(dt, robot);
      b = copy.Poses();
      tb += dt;
    }
    const double f = tb > ta ? std::clamp((tk - ta) / (tb - ta), 0.0, 1.0) : 1.0;
    for (std::size_t i = 0; i < people_.size(); ++i) {
      const MoverPose& p = tb > ta ? a[i] : b[i];
      const MoverPose& q = b[i];
      out[i].push_back(
          {p.x + f * (q.x - p.x), p.y + f * (q.y - p.y), p.yaw + f * Wrap(q.yaw - p.yaw)});
    }
  }
  return out;
}

}  // namespace mopad::sim
