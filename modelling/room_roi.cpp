// The RoI B-rep (RoomModel::BuildRoi, modelling/roi.h): the prism of the perimeter between floor
// and ceiling with the columns as holes; its faces rasterised into cells.
#include <algorithm>
#include <cmath>
#include <vector>

#include "modelling/room_model.h"

namespace mopad::modelling {

namespace {

// A horizontal RoI face (floor or ceiling) at height z over the plan bounding box [lo, hi]:
// cells inside the RoI's plan are unsensed, the others off.
RoiFace HorizontalFace(const Roi& roi, FaceKind kind, double z, const Vec2& lo, const Vec2& hi,
                       double plan_area, double cell) {
  RoiFace f;
  f.kind = kind;
  f.normal = kind == FaceKind::kFloor ? Vec3(0, 0, -1) : Vec3(0, 0, 1);
  f.area = plan_area;
  f.origin = Vec3(lo.x(), lo.y(), z);
  f.u_axis = Vec3::UnitX();
  f.v_axis = Vec3::UnitY();
  f.cell = cell;
  f.nu = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)));
  f.nv = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)));
  f.cells.assign(static_cast<std::size_t>(f.nu) * f.nv, FaceCell::kOff);
  f.cell_area.assign(f.cells.size(), 0.0f);
  for (int iv = 0; iv < f.nv; ++iv) {
    for (int iu = 0; iu < f.nu; ++iu) {
      const Vec2 c = lo + cell * Vec2(iu + 0.5, iv + 0.5);
      if (roi.ContainsPlan(c)) {
        f.cells[static_cast<std::size_t>(iv) * f.nu + iu] = FaceCell::kUnsensed;
        f.cell_area[static_cast<std::size_t>(iv) * f.nu + iu] = static_cast<float>(cell * cell);
      }
    }
  }
  return f;
}

// A vertical RoI face (wall or column face) from plan point a to b, floor zf to zf + H, with
// outward normal n_out; its cells unsensed, the last row and column cut to the face.
RoiFace VerticalFace(FaceKind kind, int element, const Vec2& a, const Vec2& b, const Vec2& n_out,
                     std::vector<int> loop, double zf, double H, double cell) {
  RoiFace f;
  f.kind = kind;
  f.element = element;
  f.loop = std::move(loop);
  f.normal = Vec3(n_out.x(), n_out.y(), 0.0);
  const double len = (b - a).norm();
  f.area = len * H;
  const Vec2 t = (b - a) / std::max(len, 1e-12);
  f.origin = Vec3(a.x(), a.y(), zf);
  f.u_axis = Vec3(t.x(), t.y(), 0.0);
  f.v_axis = Vec3::UnitZ();
  f.cell = cell;
  f.nu = std::max(1, static_cast<int>(std::ceil(len / cell)));
  f.nv = std::max(1, static_cast<int>(std::ceil(H / cell)));
  f.cells.assign(static_cast<std::size_t>(f.nu) * f.nv, FaceCell::kUnsensed);
  f.cell_area.resize(f.cells.size());
  for (int iv = 0; iv < f.nv; ++iv) {
    const double hv = std::min(cell, H - iv * cell);
    for (int iu = 0; iu < f.nu; ++iu) {
      const double hu = std::min(cell, len - iu * cell);
      f.cell_area[static_cast<std::size_t>(iv) * f.nu + iu] = static_cast<float>(hu * hv);
    }
  }
  return f;
}

// Edges of one prism ring: the floor and ceiling edges of each side face and the vertical
// corners between consecutive side faces (faces face_first .. face_first + m - 1).
void AddRingEdges(Roi& roi, const std::vector<int>& b, const std::vector<int>& t, int face_first) {
  const int m = static_cast<int>(b.size());
  for (int i = 0; i < m; ++i) {
    roi.edges.push_back({b[i], b[(i + 1) % m], 0, face_first + i});
    roi.edges.push_back({t[i], t[(i + 1) % m], 1, face_first + i});
    roi.edges.push_back({b[i], t[i], face_first + (i + m - 1) % m, face_first + i});
  }
}

}  // namespace

void RoomModel::BuildRoi() {
  Roi& roi = roi_;
  roi.vertices.clear();
  roi.edges.clear();
  roi.faces.clear();
  roi.face_adjacency.clear();
  if (roi.perimeter.size() < 3) return;
  const double zf = roi.floor_z, zc = roi.ceiling_z, H = zc - zf, cell = params_.face_cell;
  // Faces: 0 floor, 1 ceiling, walls, column faces.
  auto add_loop_vertices = [&](const std::vector<Vec2>& loop, std::vector<int>& bottom,
                               std::vector<int>& top) {
    for (const auto& v : loop) {
      bottom.push_back(static_cast<int>(roi.vertices.size()));
      roi.vertices.emplace_back(v.x(), v.y(), zf);
      top.push_back(static_cast<int>(roi.vertices.size()));
      roi.vertices.emplace_back(v.x(), v.y(), zc);
    }
  };
  std::vector<int> pb, pt;
  add_loop_vertices(roi.perimeter, pb, pt);
  std::vector<std::vector<int>> cb(roi.columns.size()), ct(roi.columns.size());
  for (std::size_t k = 0; k < roi.columns.size(); ++k)
    add_loop_vertices(roi.columns[k], cb[k], ct[k]);

  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : roi.perimeter) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  double plan_area = std::abs(SignedArea(roi.perimeter));
  for (const auto& c : roi.columns) plan_area -= std::abs(SignedArea(c));
  RoiFace floor = HorizontalFace(roi, FaceKind::kFloor, zf, lo, hi, plan_area, cell);
  floor.loop.assign(pb.rbegin(), pb.rend());
  for (std::size_t k = 0; k < roi.columns.size(); ++k) floor.holes.push_back(cb[k]);
  RoiFace ceiling = HorizontalFace(roi, FaceKind::kCeiling, zc, lo, hi, plan_area, cell);
  ceiling.loop = pt;
  for (std::size_t k = 0; k < roi.columns.size(); ++k)
    ceiling.holes.emplace_back(ct[k].rbegin(), ct[k].rend());
  roi.faces.push_back(std::move(floor));
  roi.faces.push_back(std::move(ceiling));

  const int n = static_cast<int>(roi.perimeter.size());
  const int wall0 = 2;
  for (int i = 0; i < n; ++i) {
    const Vec2 a = roi.perimeter[i], b = roi.perimeter[(i + 1) % n];
    const Vec2 t = (b - a).normalized();
    roi.faces.push_back(VerticalFace(FaceKind::kWall, i, a, b, Vec2(t.y(), -t.x()),
                                     {pb[i], pb[(i + 1) % n], pt[(i + 1) % n], pt[i]}, zf, H,
                                     cell));
  }
  std::vector<int> col0(roi.columns.size());
  for (std::size_t k = 0; k < roi.columns.size(); ++k) {
    col0[k] = static_cast<int>(roi.faces.size());
    const auto& c = roi.columns[k];
    const int m = static_cast<int>(c.size());
    for (int i = 0; i < m; ++i) {
      const Vec2 a = c[i], b = c[(i + 1) % m];
      const Vec2 t = (b - a).normalized();
      roi.faces.push_back(
          VerticalFace(FaceKind::kColumn, static_cast<int>(k), a, b, Vec2(-t.y(), t.x()),
                       {cb[k][(i + 1) % m], cb[k][i], ct[k][i], ct[k][(i + 1) % m]}, zf, H, cell));
    }
  }
  // Edges: floor and ceiling rings, vertical corners; then each face's neighbours.
  AddRingEdges(roi, pb, pt, wall0);
  for (std::size_t k = 0; k < roi.columns.size(); ++k) AddRingEdges(roi, cb[k], ct[k], col0[k]);
  roi.face_adjacency.assign(roi.faces.size(), {});
  for (const auto& e : roi.edges) {
    roi.face_adjacency[e.face0].push_back(e.face1);
    roi.face_adjacency[e.face1].push_back(e.face0);
  }
  for (auto& adj : roi.face_adjacency) {
    std::sort(adj.begin(), adj.end());
    adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
  }
}

}  // namespace mopad::modelling
