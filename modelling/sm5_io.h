#pragma once
// sm5.json (docs/models.md, format version 1): SM5 = SM4 + the room's small building service
// components, map frame, metres:
//   {"format": "mopad-sm5", "version": 1, "room": "R1",
//    "components": [{"id": "bsc_1", "class": "switch", "host": "wall_3",
//                    "centre": [x, y, z], "normal": [x, y, z], "size": [w, h, d],
//                    "alpha": 0.95, "found_by": "colour+depth"}]}
// `centre` lies on the host plane, `normal` is the host's unit normal into the room, `size` the
// class's width (along the host's horizontal axis; on a ceiling along the map's x), height and
// depth, `found_by` one of colour+depth, colour, depth. Read back by the evaluator.
// Deterministic text (values rounded to 0.1 mm / 1e-4, stable order).

#include <string>

#include "modelling/components.h"

namespace mopad::modelling {

std::string Sm5Json(const Sm5Model& model);
/// Parses sm5.json text; `where` names it in errors. InputError for a wrong format or version,
/// a missing or mistyped field, an unknown found_by, a centre, normal or size that is not 3
/// finite numbers, or an alpha outside [0, 1].
Sm5Model ParseSm5(const std::string& text, const std::string& where);
/// Reads `path` (InputError if missing or malformed, see ParseSm5).
Sm5Model ReadSm5(const std::string& path);
/// Writes `<dir>/sm5.json`; `dir` must exist. InputError on I/O failure.
void WriteSm5File(const std::string& dir, const Sm5Model& model);

}  // namespace mopad::modelling
