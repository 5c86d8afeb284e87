#include "scenes/scene_paths.h"

#include "common/error.h"
#include "scenes/generator.h"
#include "scenes/scene_loader.h"
#include "scenes/scene_spec.h"

namespace mopad::scenes {

ScenePaths ResolveScene(const std::string& arg) {
  namespace fs = std::filesystem;
  std::error_code ec;
  ScenePaths out;
  if (fs::is_directory(arg, ec)) {
    const fs::path glb = fs::path(arg) / "scene.glb";
    if (!fs::is_regular_file(glb, ec))
      throw InputError(arg, "scene folder has no scene.glb", "",
                       "a folder written by "
                       "`mopad scene generate`, or a scene file");
    out.geometry = glb.string();
    const fs::path truth = fs::path(arg) / "scene.truth.json";
    if (fs::is_regular_file(truth, ec)) out.truth = truth.string();
    return out;
  }
  if (!fs::is_regular_file(arg, ec)) throw InputError(arg, "no such scene file or folder");
  out.geometry = arg;
  // A sidecar beside the file: X.glb -> X.truth.json, or scene.truth.json in the same folder.
  const fs::path p(arg);
  for (const fs::path& cand :
       {fs::path(p).replace_extension(".truth.json"), p.parent_path() / "scene.truth.json"}) {
    if (fs::is_regular_file(cand, ec)) {
      out.truth = cand.string();
      break;
    }
  }
  return out;
}

LoadedScene LoadSceneArg(const std::string& arg, const DoorAngles& spec_door_angles,
                         const std::string& option) {
  LoadedScene out;
  const std::string ext = std::filesystem::path(arg).extension().string();
  if (ext == ".yaml" || ext == ".yml") {
    SceneSpec spec = LoadSceneSpec(arg);
    SetDoorAngles(spec_door_angles, option, &spec);
    GeneratedScene g = Generate(spec);
    out.scene = std::move(g.scene);
    out.truth = std::move(g.truth);
    out.description = arg + " (generated)";
    return out;
  }
  if (!spec_door_angles.empty()) throw InputError(option, "only with a scene spec (.yaml)");
  const ScenePaths paths = ResolveScene(arg);
  if (paths.truth) out.truth = ReadGroundTruth(*paths.truth);
  out.scene = LoadScene(paths.geometry);
  out.description = paths.geometry + (paths.truth ? " + " + *paths.truth : "");
  return out;
}

}  // namespace mopad::scenes
