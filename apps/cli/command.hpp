#pragma once
// Subcommand registry of the `spinmotor` tool. Each cmd_<name>.cpp defines one subcommand and
// registers it with a static `RegisterCommand`; main.cpp only parses and maps errors to exit codes:
//   0 ok, 2 bad input (spinmotor::Error::Kind::BadInput, or a usage error), 3 numerical failure,
//   128 + signal (130 SIGINT, 143 SIGTERM, 129 SIGHUP) for a long run stopped between frames (Interrupted);
//   any other command stopped by one of them ends by the signal (a shell reports 128 + signal too).
#include <CLI/CLI.hpp>
#include <functional>
#include <stdexcept>
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

/// Thrown by a command that stopped early on a signal (core/interrupt.hpp), once what it completed is
/// on disk: main() prints "spinmotor: interrupted by SIGINT: <what()>" on stderr and exits with
/// 128 + signal, the status a shell gives a process the signal killed.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal_(signal) {}
  int signal() const noexcept { return signal_; }

 private:
  int signal_;
};

struct RegisterCommand {
  RegisterCommand(std::string name, std::string description, std::function<void(CLI::App&)> setup) {
    commands().push_back({std::move(name), std::move(description), std::move(setup)});
  }
};

}  // namespace spinmotor::cli
