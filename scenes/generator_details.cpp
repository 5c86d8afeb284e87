// The generator's building details (scenes/details_params.h): skirting boards and ceiling trims
// along every wall, cable ducts under the ceiling, pipes in corners, posters, pictures and
// whiteboards on the walls, and how a door looks (a frame in the wall's paint, a glazed leaf).
// Every draw comes from the details' own seed, so the rest of a scene does not depend on whether
// it has details (scenes/generator_internal.h).
#include <algorithm>
#include <array>
#include <cmath>

#include "common/frames.h"
#include "scenes/generator_internal.h"

namespace mopad::scenes::gen {
namespace {

constexpr double kAlong = 0.1;          // m, spacing of the points that test a wall stretch
constexpr double kStandOff = 0.15;      // m, furniture this close to a wall hides what is on it
constexpr int kDetailAttempts = 60;     // random tries per duct, pipe and poster
constexpr double kDuctHeight = 0.12;    // m, cable trunking 120 x 60 mm
constexpr double kDuctDepth = 0.06;     // m
constexpr double kDuctMinLength = 1.0;  // m
constexpr double kPipeGap = 0.02;       // m, pipe to wall

// Paints and plastics of the details, linear RGB (docs/realism.md, "Building details").
const std::array<MaterialSpec, 3> kSkirting = {{{{0.85, 0.85, 0.83}, 0.5, 0.0, 0.0, -1.0},
                                                {{0.18, 0.18, 0.19}, 0.6, 0.0, 0.0, -1.0},
                                                {{0.52, 0.38, 0.24}, 0.6, 0.0, 0.0, -1.0}}};
const MaterialSpec kTrim{{0.90, 0.90, 0.89}, 0.8, 0.0, 0.0, -1.0};
const MaterialSpec kDuct{{0.88, 0.88, 0.85}, 0.4, 0.0, 0.0, -1.0};
const std::array<MaterialSpec, 2> kPipe = {
    {{{0.90, 0.90, 0.90}, 0.4, 0.0, 0.0, -1.0}, {{0.62, 0.62, 0.64}, 0.3, 0.8, 0.0, -1.0}}};
// Print colours of posters and pictures: saturated and pale, dark and light.
const std::array<Rgb, 10> kPrint = {{{0.70, 0.08, 0.08},
                                     {0.08, 0.18, 0.55},
                                     {0.90, 0.78, 0.15},
                                     {0.15, 0.45, 0.22},
                                     {0.90, 0.45, 0.10},
                                     {0.04, 0.04, 0.05},
                                     {0.92, 0.92, 0.90},
                                     {0.45, 0.47, 0.50},
                                     {0.10, 0.50, 0.52},
                                     {0.40, 0.15, 0.45}}};
const MaterialSpec kBoard{{0.93, 0.93, 0.92}, 0.15, 0.0, 0.0, -1.0};  // whiteboard: glossy
const MaterialSpec kMetal{{0.70, 0.71, 0.73}, 0.3, 0.9, 0.0, -1.0};   // its aluminium frame
const MaterialSpec kPictureFrame{{0.08, 0.08, 0.08}, 0.5, 0.0, 0.0, -1.0};

/// A count with mean `mean`: its whole part, and one more with the fraction's probability.
int CountOf(CounterRng& rng, double mean) {
  const double whole = std::floor(mean);
  return static_cast<int>(whole) + (rng.Bernoulli(mean - whole) ? 1 : 0);
}

}  // namespace

Generator::DoorLook Generator::LookOfDoor(const DoorSpec& ds) const {
  const DetailsParams& p = spec_.details;
  DoorLook look;
  if (!p.Enabled()) return look;
  CounterRng rng(p.seed, "scenes/details/door/" + ds.id);
  const double frame = rng.Uniform(), shade = rng.Uniform(0.92, 1.0), glazed = rng.Uniform();
  if (frame < p.frames_in_wall_colour) look.frame_shade = shade;
  look.glazed = glazed < p.glazed_doors;
  return look;
}

Generator::Glazing Generator::GlazingOf(double leaf_width, double leaf_top) {
  // Stiles 0.12 m, a 0.3 m bottom rail (the base LRF at 0.25 m still sees a closed leaf), a
  // 0.2 m top rail, an 8 mm pane.
  const double stile = std::min(0.12, 0.25 * leaf_width);
  return {stile, leaf_width - stile, 0.3, std::max(0.31, leaf_top - 0.2), 0.008};
}

Face& Generator::WallOfRoom(CounterRng& rng, const RoomData& r) {
  std::vector<double> length;
  for (int fi : r.faces) length.push_back(faces_[fi].length);
  return faces_[r.faces[PickWeighted(rng, length)]];
}

std::vector<std::pair<double, double>> Generator::FreePieces(const Face& f, double v0, double v1,
                                                             double margin) const {
  std::vector<std::pair<double, double>> cuts;
  for (const Rect2& k : f.keep_out) {
    const Rect2 r = k.Expanded(margin);
    if (r.v0 < v1 && v0 < r.v1 && r.u0 < f.length && 0.0 < r.u1) cuts.emplace_back(r.u0, r.u1);
  }
  std::sort(cuts.begin(), cuts.end());
  std::vector<std::pair<double, double>> pieces;
  double u = 0.0;
  for (const auto& [c0, c1] : cuts) {
    if (c0 > u) pieces.emplace_back(u, c0);
    u = std::max(u, c1);
  }
  if (u < f.length) pieces.emplace_back(u, f.length);
  return pieces;
}

std::pair<double, double> Generator::FreeStretch(const Face& f, double v0, double v1,
                                                 double margin) const {
  std::pair<double, double> best{0.0, 0.0};
  for (const auto& p : FreePieces(f, v0, v1, margin))
    if (p.second - p.first > best.second - best.first) best = p;
  return best;
}

void Generator::AddDetail(const std::string& type, const Face& f, const Vector3d& lo,
                          const Vector3d& hi, int material, int skip) {
  const int n = ++detail_counts_[type];
  const std::string id = type + "_" + std::to_string(n);
  const std::string& room = rooms_[f.room].id;
  MeshPart part = NewPart(id, id, ElementClass::kClutter, type, room, material);
  PartBuilder pb(&part);
  const Vector3d o = f.P(0, 0), ex = Flat(f.dir), ey = Flat(f.n_in), ez = Vector3d::UnitZ();
  AddOrientedBox(pb, o, ex, ey, ez, lo, hi, skip);
  Push(std::move(part));
  FurnitureItem item;
  item.id = id;
  item.type = type;
  item.room = room;
  const Vector3d m = 0.5 * (lo + hi);
  item.centre = f.P(m.x(), m.z(), m.y());
  item.yaw = std::atan2(f.dir.y(), f.dir.x());
  item.size = (hi - lo).cwiseAbs();
  out_.truth.details.push_back(item);
}

void Generator::AddSkirtingAndTrims() {
  const DetailsParams& p = spec_.details;
  CounterRng rng(p.seed, "scenes/details/paint");
  const MaterialSpec& board = kSkirting[rng.Below(kSkirting.size())];
  for (const Face& f : faces_) {
    // A board runs along the wall and butts the casings of its openings (their keep-out zones
    // less the component margin) and any component that reaches down or up to it.
    if (p.skirting_height > 0.0) {
      const int mat = Mat("skirting", board);
      for (const auto& [u0, u1] : FreePieces(f, 0.0, p.skirting_height, -kBscMargin))
        if (u1 - u0 > 0.05)
          AddDetail("skirting", f, {u0, 0.0, 0.0}, {u1, p.skirting_depth, p.skirting_height}, mat,
                    16);
    }
    if (p.ceiling_trim_height > 0.0) {
      const int mat = Mat("ceiling_trim", kTrim);
      const double h = f.height();
      for (const auto& [u0, u1] : FreePieces(f, h - p.ceiling_trim_height, h, -kBscMargin))
        if (u1 - u0 > 0.05)
          AddDetail("ceiling_trim", f, {u0, 0.0, h - p.ceiling_trim_height},
                    {u1, p.ceiling_trim_depth, h}, mat, 32);
    }
  }
}

void Generator::AddDucts(CounterRng& rng) {
  const DetailsParams& p = spec_.details;
  const int mat = Mat("duct", kDuct);
  for (const RoomData& r : rooms_) {
    const int n = CountOf(rng, p.ducts_per_room);
    for (int k = 0; k < n; ++k)
      for (int a = 0; a < kDetailAttempts; ++a) {
        Face& f = WallOfRoom(rng, r);
        // Under the ceiling (and its trim), along the longest free stretch of the wall.
        const double v1 = f.height() - std::max(p.ceiling_trim_height, 0.0) - 0.08;
        const double v0 = v1 - kDuctHeight;
        const auto [u0, u1] = FreeStretch(f, v0, v1, 0.0);
        if (u1 - u0 < kDuctMinLength) continue;
        AddDetail("duct", f, {u0, 0.0, v0}, {u1, kDuctDepth, v1}, mat);
        f.keep_out.push_back(Rect2{u0, u1, v0, v1});
        break;
      }
  }
}

void Generator::AddPipes(CounterRng& rng) {
  const DetailsParams& p = spec_.details;
  for (std::size_t ri = 0; ri < rooms_.size(); ++ri) {
    const RoomData& r = rooms_[ri];
    const int n = CountOf(rng, p.pipes_per_room);
    for (int k = 0; k < n; ++k)
      for (int a = 0; a < kDetailAttempts; ++a) {
        // A corner of the room between face `in` (ending there) and face `out` (starting).
        const std::size_t c = rng.Below(r.faces.size());
        const double radius = rng.Uniform(0.025, 0.055);
        const MaterialSpec& paint = kPipe[rng.Below(kPipe.size())];
        Face& fa = faces_[r.faces[c]];
        Face& fb = faces_[r.faces[(c + 1) % r.faces.size()]];
        if (fa.dir.x() * fb.dir.y() - fa.dir.y() * fb.dir.x() < 0.2) continue;  // reflex, flat
        // The centre stands radius + gap off both walls: n_a . x = d, n_b . x = d from b's start.
        const double d = radius + kPipeGap;
        Eigen::Matrix2d A;
        A << fa.n_in.x(), fa.n_in.y(), fb.n_in.x(), fb.n_in.y();
        const Vector2d centre = fb.a + A.inverse() * Vector2d(d, d);
        const double ua = (centre - fa.a).dot(fa.dir), ub = (centre - fb.a).dot(fb.dir);
        const Rect2 on_a{ua - radius, ua + radius, 0.0, fa.height()};
        const Rect2 on_b{ub - radius, ub + radius, 0.0, fb.height()};
        bool ok = true;
        for (const Rect2& ko : fa.keep_out) ok = ok && !ko.Overlaps(on_a);
        for (const Rect2& ko : fb.keep_out) ok = ok && !ko.Overlaps(on_b);
        for (const FurnitureBox& b : furniture_)
          ok = ok && (b.room != static_cast<int>(ri) ||
                      DistanceToConvex(centre, b.footprint) > radius + 0.02);
        for (const FurnitureBox& b : columns_)
          ok = ok && (b.room != static_cast<int>(ri) ||
                      DistanceToConvex(centre, b.footprint) > radius + 0.02);
        for (int di : DoorsOfRoom(static_cast<int>(ri))) {
          const DoorData& dd = doors_[di];
          ok = ok && DistanceToConvex(centre, DoorZone(dd, static_cast<int>(ri))) > radius;
          if (SwingRoom(dd) == static_cast<int>(ri))
            ok = ok && DistanceToConvex(centre, SwingZone(dd)) > radius;
        }
        if (!ok) continue;
        const int n_id = ++detail_counts_["pipe"];
        const std::string id = "pipe_" + std::to_string(n_id);
        std::string mname = "pipe";
        AppendNumber(paint.metallic, &mname);
        MeshPart part = NewPart(id, id, ElementClass::kClutter, "pipe", r.id, Mat(mname, paint));
        PartBuilder pb(&part);
        Polygon2 ring;
        constexpr int kSides = 16;
        for (int s = 0; s < kSides; ++s) {
          const double t = 2.0 * kPi * s / kSides;
          ring.push_back(centre + radius * Vector2d(std::cos(t), std::sin(t)));
        }
        pb.AddPrism(ring, r.z0, r.z1, false);
        Push(std::move(part));
        FurnitureItem item;
        item.id = id;
        item.type = "pipe";
        item.room = r.id;
        item.centre = Lift(centre, 0.5 * (r.z0 + r.z1));
        item.size = {2 * radius, 2 * radius, r.z1 - r.z0};
        out_.truth.details.push_back(item);
        fa.keep_out.push_back(on_a);
        fb.keep_out.push_back(on_b);
        break;
      }
  }
}

void Generator::AddPosters(CounterRng& rng) {
  const DetailsParams& p = spec_.details;
  for (std::size_t ri = 0; ri < rooms_.size(); ++ri) {
    const RoomData& r = rooms_[ri];
    const int n = CountOf(rng, p.posters_per_room);
    for (int k = 0; k < n; ++k)
      for (int a = 0; a < kDetailAttempts; ++a) {
        Face& f = WallOfRoom(rng, r);
        // Poster (A1 or A0 upright), framed picture (landscape) or whiteboard.
        const double kind = rng.Uniform();
        const bool board = kind >= 0.85, picture = !board && kind >= 0.6;
        double width = 0.0, height = 0.0, depth = 0.0, vc = 0.0;
        if (board) {
          width = rng.Uniform(1.2, 1.5), height = rng.Uniform(0.9, 1.2), depth = 0.015;
          vc = rng.Uniform(1.3, 1.45);
        } else if (picture) {
          width = rng.Uniform(0.5, 1.0), height = width * rng.Uniform(0.6, 0.8), depth = 0.02;
          vc = rng.Uniform(1.4, 1.7);
        } else {
          const bool a0 = rng.Bernoulli(0.4);
          width = a0 ? 0.841 : 0.594, height = a0 ? 1.189 : 0.841, depth = 0.003;
          vc = rng.Uniform(1.4, 1.7);
        }
        const Rect2 rect{0, width, vc - 0.5 * height, vc + 0.5 * height};
        if (f.length < width + 0.2 || rect.v1 > f.height() - 0.15) continue;
        const double u0 = rng.Uniform(0.1, f.length - width - 0.1);
        const Rect2 at{u0, u0 + width, rect.v0, rect.v1};
        bool ok = true;
        for (const Rect2& ko : f.keep_out) ok = ok && !ko.Overlaps(at, 0.05);
        // Nothing tall stands in front of it (furniture this close to the wall would hide it).
        for (double u = at.u0; ok && u <= at.u1; u += kAlong)
          for (const FurnitureBox& b : furniture_)
            ok = ok && (b.room != static_cast<int>(ri) ||
                        DistanceToConvex(f.Plan(u, 0.01), b.footprint) > kStandOff);
        if (!ok) continue;
        const std::string type = board ? "whiteboard" : picture ? "picture" : "poster";
        const int n_id = ++detail_counts_[type];
        const std::string id = type + "_" + std::to_string(n_id);
        const Vector3d o = f.P(0, 0), ex = Flat(f.dir), ey = Flat(f.n_in), ez = Vector3d::UnitZ();
        // Parts of one material each: the board or print, then what lies on it.
        auto part = [&](const std::string& mname, const MaterialSpec& m,
                        const std::vector<std::pair<Vector3d, Vector3d>>& boxes) {
          MeshPart mp =
              NewPart(id + "/" + mname, id, ElementClass::kClutter, type, r.id, Mat(mname, m));
          PartBuilder pb(&mp);
          for (const auto& [lo, hi] : boxes) AddOrientedBox(pb, o, ex, ey, ez, lo, hi, 4);
          Push(std::move(mp));
        };
        auto print = [&](std::size_t c) {
          MaterialSpec m{kPrint[c], 0.7, 0.0, 0.0, -1.0};
          return std::pair<std::string, MaterialSpec>("print_" + std::to_string(c), m);
        };
        const double x0 = at.u0, x1 = at.u1, y0 = at.v0, y1 = at.v1;
        if (board) {
          const double b = 0.02;  // frame
          part("whiteboard", kBoard, {{{x0 + b, 0.0, y0 + b}, {x1 - b, depth - 0.002, y1 - b}}});
          part("whiteboard_frame", kMetal,
               {{{x0, 0.0, y0}, {x1, depth, y0 + b}},
                {{x0, 0.0, y1 - b}, {x1, depth, y1}},
                {{x0, 0.0, y0 + b}, {x0 + b, depth, y1 - b}},
                {{x1 - b, 0.0, y0 + b}, {x1, depth, y1 - b}}});
        } else {
          // A background and an image on it (a poster adds a title band), each its own colour.
          const std::size_t c0 = rng.Below(kPrint.size());
          const std::size_t c1 = (c0 + 1 + rng.Below(kPrint.size() - 1)) % kPrint.size();
          const std::size_t c2 = (c1 + 1 + rng.Below(kPrint.size() - 1)) % kPrint.size();
          const double b = picture ? 0.03 : 0.0;
          const double iw = (x1 - x0 - 2 * b), ih = (y1 - y0 - 2 * b);
          if (picture) {
            part("picture_frame", kPictureFrame,
                 {{{x0, 0.0, y0}, {x1, depth, y0 + b}},
                  {{x0, 0.0, y1 - b}, {x1, depth, y1}},
                  {{x0, 0.0, y0 + b}, {x0 + b, depth, y1 - b}},
                  {{x1 - b, 0.0, y0 + b}, {x1, depth, y1 - b}}});
          }
          const double dz = picture ? depth - 0.005 : depth;
          const auto [n0, m0] = print(c0);
          part(n0, m0, {{{x0 + b, 0.0, y0 + b}, {x1 - b, dz, y1 - b}}});
          const auto [n1, m1] = print(c1);
          const double ix0 = x0 + b + 0.1 * iw, ix1 = x1 - b - 0.1 * iw;
          const double iy0 = y0 + b + (picture ? 0.1 : 0.3) * ih, iy1 = y1 - b - 0.1 * ih;
          part(n1, m1, {{{ix0, dz, iy0}, {ix1, dz + 0.001, iy1}}});
          if (!picture) {
            const auto [n2, m2] = print(c2);
            part(n2, m2, {{{ix0, dz, y0 + 0.08 * ih}, {ix1, dz + 0.001, y0 + 0.22 * ih}}});
          }
        }
        FurnitureItem item;
        item.id = id;
        item.type = type;
        item.room = r.id;
        item.centre = f.P(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * depth);
        item.yaw = std::atan2(f.dir.y(), f.dir.x());
        item.size = {width, depth, height};
        out_.truth.details.push_back(item);
        f.keep_out.push_back(at);
        break;
      }
  }
}

void Generator::PlaceDetails() {
  const DetailsParams& p = spec_.details;
  if (!p.Enabled()) return;
  AddSkirtingAndTrims();
  CounterRng ducts(p.seed, "scenes/details/ducts"), pipes(p.seed, "scenes/details/pipes"),
      posters(p.seed, "scenes/details/posters");
  AddDucts(ducts);
  AddPipes(pipes);
  AddPosters(posters);
}

}  // namespace mopad::scenes::gen
