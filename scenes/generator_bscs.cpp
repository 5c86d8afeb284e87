// The generator's building service components: catalogue models placed explicitly, at random
// on walls and ceilings, or by rules relative to doors, windows and other components, each
// clear of openings, columns and the others (scenes/generator_internal.h).
#include <algorithm>
#include <set>

#include "common/error.h"
#include "scenes/generator_internal.h"

namespace mopad::scenes::gen {

void Generator::AddBscGeometry(const std::string& id, const std::string& cls,
                               const std::string& room, const Vector3d& o, const Vector3d& ex,
                               const Vector3d& ey, const Vector3d& ez) {
  auto it = bsc_models_.find(cls);
  if (it == bsc_models_.end()) {
    Scene model = BuildBscModel(cls);
    const int tex_base = static_cast<int>(out_.scene.textures.size());
    for (auto& t : model.textures) out_.scene.textures.push_back(t);
    std::vector<int> mat_map;
    for (auto m : model.materials) {
      if (m.base_color_texture >= 0) m.base_color_texture += tex_base;
      mat_map.push_back(static_cast<int>(out_.scene.materials.size()));
      out_.scene.materials.push_back(m);
    }
    for (auto& p : model.parts) p.material = p.material >= 0 ? mat_map[p.material] : -1;
    it = bsc_models_.emplace(cls, std::move(model)).first;
  }
  for (const MeshPart& mp : it->second.parts) {
    MeshPart p = mp;
    std::string suffix = mp.name;
    if (suffix.rfind(cls, 0) == 0) suffix = suffix.substr(cls.size());
    if (!suffix.empty() && suffix[0] == '_') suffix = suffix.substr(1);
    p.name = id + "/" + (suffix.empty() ? "body" : suffix);
    p.element_id = id;
    p.element_class = ElementClass::kServiceComponent;
    p.subclass = cls;
    p.room = room;
    for (auto& v : p.positions) {
      const Vector3d l = v.cast<double>();
      v = (o + l.x() * ex + l.y() * ey + l.z() * ez).cast<float>();
    }
    Push(std::move(p));
  }
}

std::string Generator::NextBscId(const std::string& cls) {
  return cls + "_" + std::to_string(++bsc_counts_[cls]);
}

bool Generator::WallSpotFree(int face, const Rect2& rect, double depth) const {
  const Face& f = faces_[face];
  const double end = depth + 0.05;
  if (rect.u0 < end || rect.u1 > f.length - end || rect.v0 < 0.05 || rect.v1 > f.height() - 0.05)
    return false;
  for (const auto& k : f.keep_out)
    if (rect.Overlaps(k)) return false;
  const Vector2d c = f.Plan(0.5 * (rect.u0 + rect.u1), 0.5 * depth);
  for (const auto& col : columns_)
    if (col.room == f.room &&
        DistanceToConvex(c, col.footprint) < 0.5 * (rect.u1 - rect.u0) + depth + 0.15)
      return false;
  return true;
}

Rect2 Generator::StackRect(const Rect2& rect, const BscSpec& stack, double v_default) {
  const double v = std::max(v_default, rect.v1 + kBscMargin + 0.07 + 0.5 * stack.height);
  const double u = 0.5 * (rect.u0 + rect.u1);
  return {u - 0.5 * stack.width, u + 0.5 * stack.width, v - 0.5 * stack.height,
          v + 0.5 * stack.height};
}

const BscSpecEntry* Generator::StackedOver(const std::string& cls, std::size_t after) const {
  for (std::size_t i = after + 1; i < spec_.bscs.size(); ++i)
    if (spec_.bscs[i].placement == "above" && spec_.bscs[i].above == cls) return &spec_.bscs[i];
  return nullptr;
}

void Generator::PlaceWallBsc(const BscSpec& cat, int face, double u, double v,
                             const std::string& room, const Rect2* reserve) {
  Face& f = faces_[face];
  WallBsc b;
  b.id = NextBscId(cat.class_name);
  b.cls = cat.class_name;
  b.room = room;
  b.face = face;
  b.rect = {u - 0.5 * cat.width, u + 0.5 * cat.width, v - 0.5 * cat.height, v + 0.5 * cat.height};
  b.depth = cat.depth;
  f.keep_out.push_back(b.rect.Expanded(kBscMargin));
  if (reserve) {
    b.reservation = static_cast<int>(f.keep_out.size());
    f.keep_out.push_back(reserve->Expanded(kBscMargin));
  }
  // Model frame: x to the right seen from the room (= -dir), y up, z into the room.
  const Vector3d o = f.P(u, v, 0.0);
  AddBscGeometry(b.id, b.cls, room, o, -Flat(f.dir), Vector3d::UnitZ(), Flat(f.n_in));
  ServiceComponent sc;
  sc.id = b.id;
  sc.bsc_class = b.cls;
  sc.host = f.id;
  sc.room = room;
  sc.centre = o;
  sc.normal = Flat(f.n_in);
  sc.size = {cat.width, cat.height, cat.depth};
  out_.truth.service_components.push_back(sc);
  wall_bscs_.push_back(b);
}

void Generator::PlaceCeilingBsc(const BscSpec& cat, int room, const Vector2d& p) {
  const RoomData& r = rooms_[room];
  const std::string id = NextBscId(cat.class_name);
  const Vector3d o = Lift(p, r.z1);
  // Model frame: z down out of the ceiling; x = world x, y = -world y (right-handed).
  AddBscGeometry(id, cat.class_name, r.id, o, Vector3d::UnitX(), -Vector3d::UnitY(),
                 -Vector3d::UnitZ());
  ServiceComponent sc;
  sc.id = id;
  sc.bsc_class = cat.class_name;
  sc.host = "ceiling_" + r.id;
  sc.room = r.id;
  sc.centre = o;
  sc.normal = -Vector3d::UnitZ();
  sc.size = {cat.width, cat.height, cat.depth};
  out_.truth.service_components.push_back(sc);
  ceiling_bscs_.push_back({room, p});
}

bool Generator::CeilingSpotFree(int room, const Vector2d& p, const BscSpec& cat) const {
  const RoomData& r = rooms_[room];
  if (!PointInPolygon(p, r.poly) || DistanceToBoundary(p, r.poly) < 0.5 + cat.width) return false;
  for (const auto& c : ceiling_bscs_)
    if (c.room == room && (c.p - p).norm() < 1.0) return false;
  for (const auto& col : columns_)
    if (col.room == room && DistanceToConvex(p, col.footprint) < 0.4) return false;
  return true;
}

std::vector<int> Generator::CandidateRooms(const BscSpecEntry& e) const {
  std::vector<int> out;
  if (e.rooms.empty()) {
    for (std::size_t i = 0; i < rooms_.size(); ++i) out.push_back(static_cast<int>(i));
  } else {
    for (const auto& id : e.rooms) out.push_back(RoomIndex(id));
  }
  return out;
}

void Generator::CannotPlace(const BscSpecEntry& e, int k, const std::string& why) const {
  throw InputError(e.where, "cannot place bsc '" + e.class_name + "' #" + std::to_string(k + 1) +
                                " of " + std::to_string(e.count) + ": " + why);
}

// Each spec entry in order: explicit spots first-come, random wall/ceiling spots from the
// entry's own stream "bsc/<index>", rule spots from a shuffled candidate list.
void Generator::PlaceBscs() {
  for (std::size_t ei = 0; ei < spec_.bscs.size(); ++ei) {
    const BscSpecEntry& e = spec_.bscs[ei];
    const BscSpec& cat = *FindBsc(e.class_name);
    const double v_default = e.height >= 0.0 ? e.height : cat.default_mount_height;
    if (e.is_explicit) {
      PlaceExplicitBsc(e, cat, v_default);
      continue;
    }
    const std::vector<int> rooms = CandidateRooms(e);
    const std::string placement =
        !e.placement.empty()
            ? e.placement
            : (cat.mounting == interfaces::Mounting::kCeiling ? "ceiling" : "wall");
    if (placement == "wall" || placement == "ceiling")
      PlaceRandomBscs(ei, e, cat, rooms, placement, v_default);
    else
      PlaceRuleBscs(ei, e, cat, rooms, placement, v_default);
  }
}

void Generator::PlaceExplicitBsc(const BscSpecEntry& e, const BscSpec& cat, double v_default) {
  const int r = RoomIndex(e.room);
  if (cat.mounting == interfaces::Mounting::kCeiling) {
    if (!CeilingSpotFree(r, e.position, cat)) CannotPlace(e, 0, "ceiling spot not free");
    PlaceCeilingBsc(cat, r, e.position);
  } else {
    const int face = rooms_[r].faces[static_cast<std::size_t>(e.wall)];
    const Rect2 rect{e.u - 0.5 * cat.width, e.u + 0.5 * cat.width, v_default - 0.5 * cat.height,
                     v_default + 0.5 * cat.height};
    if (!WallSpotFree(face, rect, cat.depth))
      CannotPlace(e, 0, "wall spot on '" + faces_[face].id + "' is not free");
    PlaceWallBsc(cat, face, e.u, v_default, rooms_[r].id);
  }
}

// Component k of the entry tries up to kPlacementAttempts spots drawn from its own counter
// (stream "bsc/<ei>", index k).
void Generator::PlaceRandomBscs(std::size_t ei, const BscSpecEntry& e, const BscSpec& cat,
                                const std::vector<int>& rooms, const std::string& placement,
                                double v_default) {
  const std::string stream = "bsc/" + std::to_string(ei);
  const BscSpecEntry* stack = StackedOver(e.class_name, ei);
  for (int k = 0; k < e.count; ++k) {
    CounterRng rng(spec_.seed, stream, static_cast<std::uint64_t>(k));
    bool ok = false;
    for (int attempt = 0; attempt < kPlacementAttempts && !ok; ++attempt) {
      if (placement == "ceiling")
        ok = TryCeilingBsc(rng, cat, rooms);
      else
        ok = TryWallBsc(rng, cat, rooms, v_default, stack);
    }
    if (!ok) CannotPlace(e, k, "no free " + placement + " space in its rooms");
  }
}

// One random ceiling spot: a room by area, a point in its bounding box; placed if free.
bool Generator::TryCeilingBsc(CounterRng& rng, const BscSpec& cat, const std::vector<int>& rooms) {
  std::vector<double> w;
  for (int r : rooms) w.push_back(rooms_[r].area);
  const int r = rooms[PickWeighted(rng, w)];
  Eigen::AlignedBox2d box;
  for (const auto& p : rooms_[r].poly) box.extend(p);
  const Vector2d p(rng.Uniform(box.min().x(), box.max().x()),
                   rng.Uniform(box.min().y(), box.max().y()));
  if (!CeilingSpotFree(r, p, cat)) return false;
  PlaceCeilingBsc(cat, r, p);
  return true;
}

// One random wall spot: a face by length, a position along it; placed if free, together with
// the space held above it for the entry that stacks on this class (`stack`, may be null).
bool Generator::TryWallBsc(CounterRng& rng, const BscSpec& cat, const std::vector<int>& rooms,
                           double v_default, const BscSpecEntry* stack) {
  std::vector<int> faces;
  std::vector<double> w;
  for (int r : rooms)
    for (int fi : rooms_[r].faces) {
      faces.push_back(fi);
      w.push_back(faces_[fi].length);
    }
  const int fi = faces[PickWeighted(rng, w)];
  const Face& f = faces_[fi];
  const double u = rng.Uniform(0.0, f.length);
  const Rect2 rect{u - 0.5 * cat.width, u + 0.5 * cat.width, v_default - 0.5 * cat.height,
                   v_default + 0.5 * cat.height};
  if (!WallSpotFree(fi, rect, cat.depth)) return false;
  if (stack) {
    const BscSpec& sc = *FindBsc(stack->class_name);
    const Rect2 sr =
        StackRect(rect, sc, stack->height >= 0 ? stack->height : sc.default_mount_height);
    if (!WallSpotFree(fi, sr, sc.depth)) return false;
    PlaceWallBsc(cat, fi, u, v_default, rooms_[f.room].id, &sr);
  } else {
    PlaceWallBsc(cat, fi, u, v_default, rooms_[f.room].id);
  }
  return true;
}

// Rules relative to openings or other components: a deterministic shuffled candidate list,
// taken in order.
void Generator::PlaceRuleBscs(std::size_t ei, const BscSpecEntry& e, const BscSpec& cat,
                              const std::vector<int>& rooms, const std::string& placement,
                              double v_default) {
  const std::string stream = "bsc/" + std::to_string(ei);
  std::vector<Spot> spots, second;  // second: less preferred spots (hinge side)
  RuleSpots(e, cat, rooms, placement, v_default, &spots, &second);
  CounterRng shuffle(spec_.seed, stream + "/shuffle");
  for (auto* list : {&spots, &second})
    for (std::size_t i = list->size(); i > 1; --i)
      std::swap((*list)[i - 1], (*list)[shuffle.Below(i)]);
  spots.insert(spots.end(), second.begin(), second.end());
  std::size_t next = 0;
  for (int k = 0; k < e.count; ++k) {
    bool ok = false;
    while (next < spots.size() && !ok) ok = TakeRuleSpot(cat, spots[next++]);
    if (!ok) CannotPlace(e, k, "no free '" + placement + "' spot left");
  }
}

// The candidate spots of a rule placement in the entry's rooms, in door / window / component
// order; beside_door puts the latch side in `spots` and the hinge side in `second`.
void Generator::RuleSpots(const BscSpecEntry& e, const BscSpec& cat, const std::vector<int>& rooms,
                          const std::string& placement, double v_default, std::vector<Spot>* spots,
                          std::vector<Spot>* second) const {
  std::set<int> in_rooms(rooms.begin(), rooms.end());
  for (std::size_t di = 0; di < doors_.size(); ++di) {
    const DoorData& d = doors_[di];
    for (int fi : {d.face, d.other}) {
      if (fi < 0 || !in_rooms.count(faces_[fi].room)) continue;
      const auto [h, hinge_high] = DoorOnFace(d, fi);
      const double fw = d.spec->frame_width;
      if (placement == "beside_door") {
        const double off = fw + kBscMargin + 0.08 + 0.5 * cat.width;
        const Spot lo{fi, h.u0 - off, v_default, -1}, hi{fi, h.u1 + off, v_default, -1};
        spots->push_back(hinge_high ? lo : hi);
        second->push_back(hinge_high ? hi : lo);
      } else if (placement == "above_door") {
        const double v = std::max(v_default, h.v1 + fw + kBscMargin + 0.02 + 0.5 * cat.height);
        spots->push_back({fi, 0.5 * (h.u0 + h.u1), v, -1});
      }
    }
  }
  if (placement == "under_window") {
    for (const auto& w : windows_) {
      if (!in_rooms.count(faces_[w.face].room)) continue;
      const double top = w.hole.v0 - w.spec->frame_width - kBscMargin - 0.02;
      spots->push_back(
          {w.face, 0.5 * (w.hole.u0 + w.hole.u1), std::min(v_default, top - 0.5 * cat.height), -1});
    }
  } else if (placement == "above") {
    for (std::size_t bi = 0; bi < wall_bscs_.size(); ++bi) {
      const WallBsc& t = wall_bscs_[bi];
      if (t.cls != e.above || !in_rooms.count(faces_[t.face].room)) continue;
      const Rect2 sr = StackRect(t.rect, cat, v_default);
      spots->push_back(
          {t.face, 0.5 * (sr.u0 + sr.u1), 0.5 * (sr.v0 + sr.v1), static_cast<int>(bi)});
    }
  }
}

// Places the component at `s` if the spot is free (releasing the space held for it above its
// target); false if taken or blocked.
bool Generator::TakeRuleSpot(const BscSpec& cat, const Spot& s) {
  if (s.target >= 0 && wall_bscs_[s.target].stacked) return false;
  const Rect2 rect{s.u - 0.5 * cat.width, s.u + 0.5 * cat.width, s.v - 0.5 * cat.height,
                   s.v + 0.5 * cat.height};
  // Release the space held for this component above its target.
  Rect2 held{};
  const int res = s.target >= 0 ? wall_bscs_[s.target].reservation : -1;
  if (res >= 0) {
    held = faces_[s.face].keep_out[res];
    faces_[s.face].keep_out[res] = Rect2{-10, -10, -10, -10};
  }
  if (!WallSpotFree(s.face, rect, cat.depth)) {
    if (res >= 0) faces_[s.face].keep_out[res] = held;
    return false;
  }
  if (res >= 0) wall_bscs_[s.target].reservation = -1;
  if (s.target >= 0) wall_bscs_[s.target].stacked = true;
  PlaceWallBsc(cat, s.face, s.u, s.v, rooms_[faces_[s.face].room].id);
  return true;
}

}  // namespace mopad::scenes::gen
