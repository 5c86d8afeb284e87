#pragma once
// Third-party readers in a child process: assimp's IFC 2x3 reader and IfcPlusPlus's IFC4 reader
// can crash (segfault) on a hostile or unusual file. Run in a child, such a crash is one
// InputError naming the reader and the signal (exit code 2), never a dead `mopad`.

#include <functional>
#include <string>

#include "scenes/scene.h"

namespace mopad::scenes {

/// Runs `read_scene` in a child process (fork) and returns the Scene it made, passed back whole
/// through a pipe. `reader` names it in messages ("the IFC4 reader (IfcPlusPlus)"), `expected`
/// says what it reads ("an IFC4 file it can read"). An InputError `read_scene` throws arrives as the
/// same message; the reader crashing is InputError `path: error: <reader> crashed on this file;
/// got signal N (name), expected <expected>`; any other failure names the reader too.
Scene ReadSceneInChild(const std::string& path, const std::string& reader,
                       const std::string& expected, const std::function<Scene()>& read_scene);

}  // namespace mopad::scenes
