// `rheo`: command-line front end. Each subcommand is registered from its own file.
#include <CLI/CLI.hpp>
#include <iostream>
#include <string>

#include "host/cli/commands.hpp"
#include "host/cli/version.hpp"
#include "sim/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "rheo: real-time rheological objects (three-element particle models) on a reference\n"
      "simulator, a bit-true fixed-point model and an RTL core in Verilator."};
  app.set_version_flag("--version", rheo::cli::version_text());
  app.require_subcommand(1);
  rheo::cli::register_simulate(app);
  rheo::cli::register_fit(app);
  rheo::cli::register_diagnose(app);
  rheo::cli::register_scenarios(app);
  rheo::cli::register_synth(app);
  rheo::cli::register_cosim(app);
  rheo::cli::register_fixed(app);
  rheo::cli::register_cosim_server(app);
  rheo::cli::register_haptic_server(app);
  rheo::cli::register_bench_link(app);
  // A first word that is no command: name it (CLI11 says only that a command is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->check_name(argv[1]);
    }
    if (!known) {
      std::cerr << "rheo: error: unknown command '" << argv[1] << "', expected one of: " << names
                << "\nrheo: run 'rheo --help' for the commands\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end parsing too, successfully.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    // A usage error: exit 2, as command-line tools do, with the same prefix as every other
    // error of rheo, the option and what it expects.
    std::cerr << "rheo: error: " << e.what() << "\n"
              << "rheo: run 'rheo --help' or 'rheo SUBCOMMAND --help' for the options\n";
    return 2;
  } catch (const rheo::Error& e) {
    std::cerr << "rheo: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    // Anything else (a file system or allocation failure) still ends with a message and a
    // non-zero exit, never an abort.
    std::cerr << "rheo: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
