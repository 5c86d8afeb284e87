// `mopad`: thin command line over the OpenMoPAD libraries.
#include <cstdio>
#include <exception>

#include "common/error.h"
#include "tools/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"OpenMoPAD: simulation-driven autonomous scan-to-BIM"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "mopad 0.1.0");
  mopad::tools::RegisterSceneCommands(app);
  mopad::tools::RegisterSimCommands(app);
  mopad::tools::RegisterRunCommand(app);
  mopad::tools::RegisterDriveCommand(app);
  mopad::tools::RegisterRoomCommand(app);
  mopad::tools::RegisterEvalCommand(app);
  mopad::tools::RegisterExportCommand(app);
  mopad::tools::RegisterDatasetCommand(app);
  mopad::tools::RegisterCatalogueCommand(app);
  mopad::tools::RegisterSuiteCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    // A command's own verdict (e.g. `scene validate` found errors). RuntimeError derives from
    // ParseError in CLI11 2.x, so it must be caught first.
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    // CLI11 prints help/version (exit 0) or the usage error; usage errors all exit 2.
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const mopad::InputError& e) {
    std::fprintf(stderr, "mopad: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mopad: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
