#pragma once
// Subcommand registration for the `mopad` CLI. Each cmd_*.cpp adds its subcommands to the app
// and sets their callbacks; callbacks parse options, call the libraries, and write files.
// Errors: throw mopad::InputError for bad input (exit 2); anything else is internal (exit 3).

#include <CLI/CLI.hpp>

namespace mopad::tools {

void RegisterSceneCommands(CLI::App& app);  // scene generate|random|info|validate|catalogue
void RegisterSimCommands(CLI::App& app);    // scan, lrf, bench raycast
void RegisterRunCommand(CLI::App& app);     // run: the main job
void RegisterDriveCommand(CLI::App& app);   // drive: closed-loop navigation
void RegisterRoomCommand(CLI::App& app);    // room: autonomous scanning of one room -> SM1
void RegisterEvalCommand(CLI::App& app);    // eval: score a run's models against the truth

}  // namespace mopad::tools
