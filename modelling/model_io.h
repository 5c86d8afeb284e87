#pragma once
// Writers of the robot's model files (docs/models.md, format version 1): SM2 (the final RoI
// B-rep) and SM3 as JSON, DSM3 as a PLY of labelled voxel centres. Map frame, metres.
// InputError on I/O failure. Deterministic text (fixed float formatting, stable order).

#include <string>

#include "modelling/roi.h"
#include "modelling/structural_model.h"
#include "modelling/voxel_space.h"

namespace mopad::modelling {

inline constexpr int kModelFormatVersion = 1;

std::string Sm2Json(const Roi& roi, const std::string& room);
std::string Sm3Json(const StructuralModel& model);
/// Every voxel inside the RoI (flag kInside or on a face) with its DSM3 label and indices.
void WriteDsm3Ply(const VoxelSpace& voxels, const std::string& path);

}  // namespace mopad::modelling
