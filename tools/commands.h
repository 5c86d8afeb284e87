#pragma once
// Subcommand registration for the `mopad` CLI. Each cmd_*.cpp adds its subcommands to the app
// and sets their callbacks; callbacks parse options, call the libraries, and write files.
// Errors: throw mopad::InputError for bad input (exit 2); anything else is internal (exit 3).

#include <CLI/CLI.hpp>
#include <string>

#include "common/frames.h"

namespace mopad::tools {

void RegisterSceneCommands(CLI::App& app);  // scene generate|random|info|validate|catalogue
void RegisterSimCommands(CLI::App& app);    // scan, lrf, bench raycast
void RegisterRunCommand(CLI::App& app);     // run: the main job
void RegisterDriveCommand(CLI::App& app);   // drive: closed-loop navigation
void RegisterRoomCommand(CLI::App& app);    // room: autonomous scanning of one room -> SM1
void RegisterEvalCommand(CLI::App& app);    // eval: score a run's models against the truth
void RegisterExportCommand(CLI::App& app);  // export: IFC4, semantic glTF, LAS of a run
void RegisterDatasetCommand(CLI::App& app);  // dataset: labelled scans for offline methods
void RegisterCatalogueCommand(CLI::App& app);  // catalogue train: SM5's recogniser weights
void RegisterSuiteCommands(CLI::App& app);     // suite run|merge: CI scene suites
/// Adds `compare` and `slurm` under the `suite` subcommand.
void RegisterSuiteCompareCommands(CLI::App& suite);

/// Parses "x,y,yaw_deg" (a CLI pose option, degrees at the human edge); InputError naming
/// `opt` otherwise.
Pose2 ParsePoseArg(const std::string& opt, const std::string& text);

/// Parameter precedence, the same for every command (docs/architecture.md): a flag given on the
/// command line, over the --config file, over the built-in default. `field` takes `value` only
/// when `option` was given.
template <class T>
void OverrideIfGiven(const CLI::Option* option, const T& value, T& field) {
  if (option->count() > 0) field = value;
}

}  // namespace mopad::tools
