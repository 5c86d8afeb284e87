// placeholder: replaced by its owner (scan, lrf, bench raycast)
#include "tools/commands.h"
namespace mopad::tools {
void RegisterSimCommands(CLI::App&) {}
}  // namespace mopad::tools
