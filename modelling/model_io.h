#pragma once
// Writers of the robot's model files (docs/models.md, format version 1): SM2 (the final RoI
// B-rep), SM3 and SM4 as JSON, DSM3 as a PLY of labelled voxel centres. Map frame, metres.
// SM3 and SM4 are also read back (ReadSm3, ReadSm4), for the exports, the evaluator and round
// trips.
// InputError on I/O failure. Deterministic text (fixed float formatting, stable order).

#include <string>
#include <utility>
#include <vector>

#include "modelling/components.h"
#include "modelling/floor_model.h"
#include "modelling/openings.h"
#include "modelling/orthoimage.h"
#include "modelling/roi.h"
#include "modelling/structural_model.h"
#include "modelling/voxel_space.h"

namespace mopad::modelling {

inline constexpr int kModelFormatVersion = 1;

std::string Sm2Json(const Roi& roi, const std::string& room);
std::string Sm3Json(const StructuralModel& model);
/// sm4.json: {"format": "mopad-sm4", "version": 1, "room", "openings": [{"id", "type", "host",
/// "corners" (4 xyz, CCW seen from the room, the hole), "confidence", and for doors "state",
/// "opening_angle_deg" (null when unknown), "clear_width_m"}]} (docs/models.md).
std::string Sm4Json(const Sm4Model& model);
/// Parses sm3.json text; `where` names it in errors. InputError for a wrong format or version,
/// a missing or mistyped field, an unknown class, a polygon of fewer than 3 finite points, an
/// adjacency pair out of range.
StructuralModel ParseSm3(const std::string& text, const std::string& where);
/// Reads sm3.json (InputError if missing or malformed, see ParseSm3).
StructuralModel ReadSm3(const std::string& path);
/// Parses sm4.json text; `where` names it in errors. InputError for a wrong format or version,
/// a missing or mistyped field, an unknown type or state, corners that are not 4 finite points.
/// The (u, v) rectangle of each opening is left 0 (the file holds map-frame corners only).
Sm4Model ParseSm4(const std::string& text, const std::string& where);
/// Reads sm4.json (InputError if missing or malformed, see ParseSm4).
Sm4Model ReadSm4(const std::string& path);
/// floor/sm3.json of a FloorModel (modelling/floor_model.h; docs/models.md "The floor model"):
/// an sm3.json ("mopad-sm3", "room": "floor", so ParseSm3 and the exports read it as the floor's
/// SM3) whose patches are the floor walls (plane and polygon of the FloorWall; plus
/// "thickness_m" (null: one face), "known_side" (the room of a one-face wall, else null),
/// "faces": [{"room", "side", "patch"}], "pairs": [{"faces": [i, j], "thickness_m",
/// "overlap_m"}]), then each room's floor, ceiling and column patches (ids made unique across
/// the floor: "floor_2", columns renumbered; plus "room" and "room_patch", the room's own id);
/// "adjacency" is empty; top-level "rooms": [{"room", "floor_z", "ceiling_z"}].
std::string FloorSm3Json(const FloorModel& model);
/// floor/sm4.json: an sm4.json ("mopad-sm4", "room": "floor") whose openings' "host" is a floor
/// wall, plus per opening "rooms" and "sides": [{"room", "opening"}] (each room's own SM4
/// opening, the chosen side first).
std::string FloorSm4Json(const FloorModel& model);
/// Parses both floor files; `*_where` name them in errors. InputError for a wrong format or
/// version, an sm3.json that is not a floor's (room "floor" with "rooms"), a missing or
/// mistyped field, a room patch of an unlisted room, a wall without faces, a thickness that
/// does not fit the face count (null exactly for one face), a face side other than 1 or -1, a
/// pair index out of range, an opening with no side or more than two. The openings' (u, v)
/// rectangles are left 0.
FloorModel ParseFloorModel(const std::string& sm3_text, const std::string& sm3_where,
                           const std::string& sm4_text, const std::string& sm4_where);
/// Reads `<dir>/sm3.json` and `<dir>/sm4.json` (InputError if missing or malformed).
FloorModel ReadFloorModel(const std::string& dir);
/// Writes `<dir>/sm3.json` and `<dir>/sm4.json`; `dir` must exist. InputError on I/O failure.
void WriteFloorModelFiles(const std::string& dir, const FloorModel& model);
/// Writes `<dir>/sm4.json` and, per image, `<dir>/orthoimages/<patch id>_colour.png` and
/// `_depth.png` (WriteOrthoimagePngs). `dir` must exist; InputError on I/O failure.
void WriteSm4Files(const std::string& dir, const Sm4Model& model,
                   const std::vector<std::pair<std::string, Orthoimage>>& images);
/// models.glb (io::WriteGlb): one node per SM3 patch (walls, floor, ceiling, column faces) and,
/// with `sm4`, per opening (a quad on its hole), each with extras {"mopad": {"id", "class",
/// "room"}} and, for openings, "state" and "opening_angle_deg"; materials per class. With
/// `sm5`, per service component a box of its class's size standing on its host (width along
/// the host frame's u, height along v, depth along the normal into the room), extras "class"
/// (the catalogue class), "host", "alpha", "found_by", material "component". Patches whose
/// polygon is not counter-clockwise seen from the room are left out. InputError when nothing
/// could be triangulated or the file cannot be written.
void WriteModelsGlb(const StructuralModel& sm3, const Sm4Model* sm4, const std::string& room,
                    const std::string& path, const Sm5Model* sm5 = nullptr);
/// Every voxel inside the RoI (flag kInside or on a face) with its DSM3 label and indices.
void WriteDsm3Ply(const VoxelSpace& voxels, const std::string& path);

}  // namespace mopad::modelling
