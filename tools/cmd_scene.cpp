#include "tools/commands.h"
namespace mopad::tools {
void RegisterSceneCommands(CLI::App&) {}
void RegisterRunCommand(CLI::App&) {}
}  // namespace mopad::tools
