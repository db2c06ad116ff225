// The subcommands that list what is bundled and hand results to other tools:
// `packsim list`, `packsim export`, `packsim report`, `packsim fmu`. Registered on the CLI11 app by main.cpp with one
// call, dispatched with another.
#pragma once
#include <CLI/CLI.hpp>

#include <optional>

#include "core/cli/commands.hpp"

namespace packsim {

struct ToolCommands {
  CLI::App* list = nullptr;
  CLI::App* exportCmd = nullptr;
  ExportOptions exportOpts;
  CLI::App* reportCmd = nullptr;
  ReportOptions reportOpts;
  CLI::App* fmuCmd = nullptr;
  FmuCliOptions fmuOpts;
};

void addToolCommands(CLI::App& app, ToolCommands& t);
// The exit status of the tool command that was parsed, or nullopt if none was.
std::optional<int> runToolCommand(const ToolCommands& t);

}  // namespace packsim
