// spinmotor: the command-line tool. See `spinmotor --help` and README.md.
#include <algorithm>
#include <iostream>

#include "command.hpp"
#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/interrupt.hpp"
#include "spinmotor/core/memory_budget.hpp"
#include "spinmotor/linalg/blas_threads.hpp"

namespace spinmotor::cli {
std::vector<Command>& commands() {
  static std::vector<Command> registry;
  return registry;
}
}  // namespace spinmotor::cli

int main(int argc, char** argv) {
  using namespace spinmotor;
  // SIGINT, SIGTERM, SIGHUP: taken by a thread of their own, never by a dependency's handler (METIS
  // traps SIGTERM while it orders); a stop while writing leaves no temporary behind (interrupt.hpp).
  take_stop_signals();
  join_idle_blas_workers();  // OpenBLAS's workers from load time: they start again blocking them too
  CLI::App app{"spinmotor: deform triangle meshes with CGA motors and snap edits onto spin transformations"};
  app.set_version_flag("--version", std::string("spinmotor ") + SPINMOTOR_VERSION);
  app.require_subcommand(1);
  auto& cmds = cli::commands();
  std::sort(cmds.begin(), cmds.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  // Global: before or after the command's own arguments (subcommands fall through to it).
  app.add_option_function<std::string>(
         "--max-memory", [](const std::string& s) { set_memory_limit(parse_memory_size(s)); },
         "Refuse work whose estimated memory exceeds SIZE (e.g. 512M, 8G) at once, with the estimate; "
         "default: the memory available when the command starts")
      ->type_name("SIZE")
      ->trigger_on_parse();
  for (auto& c : cmds) c.setup(*app.add_subcommand(c.name, c.description)->fallthrough());
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  } catch (const cli::Interrupted& e) {
    std::cerr << "spinmotor: interrupted by " << signal_name(e.signal()) << ": " << e.what() << '\n';
    return interrupted_exit_code(e.signal());
  } catch (const Error& e) {
    std::cerr << "spinmotor: error: " << e.what() << '\n';
    return e.exit_code();
  } catch (const std::exception& e) {
    std::cerr << "spinmotor: internal error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
