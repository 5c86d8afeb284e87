#pragma once
// Wavefront OBJ export of a Scene (geometry, UVs, base colours in a .mtl beside it), for tools
// that do not read glTF. OBJ has no up-axis convention: we write Y-up, like glTF and most
// DCC tools, so LoadScene's default for .obj reads it back into the same Z-up world.
// One `o` object per MeshPart, named `<class>:<element_id or part name>`.

#include <string>

#include "scenes/scene.h"

namespace mopad::scenes {

/// Writes PATH (.obj) and PATH with extension .mtl. Throws InputError if they cannot be written.
void WriteObj(const Scene& scene, const std::string& path);

}  // namespace mopad::scenes
