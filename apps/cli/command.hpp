#pragma once
// Subcommand registry of the `spinmotor` tool. Each cmd_<name>.cpp defines one subcommand and
// registers it with a static `RegisterCommand`; main.cpp only parses and maps errors to exit codes:
//   0 ok, 2 bad input (spinmotor::Error::Kind::BadInput, or a usage error), 3 numerical failure.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace spinmotor::cli {

struct Command {
  std::string name;
  std::string description;
  /// Adds the subcommand's options to `sub` and sets its callback (which may throw spinmotor::Error).
  std::function<void(CLI::App& sub)> setup;
};

std::vector<Command>& commands();

struct RegisterCommand {
  RegisterCommand(std::string name, std::string description, std::function<void(CLI::App&)> setup) {
    commands().push_back({std::move(name), std::move(description), std::move(setup)});
  }
};

}  // namespace spinmotor::cli
