// `rheo scenarios`: lists the built-in scenarios, or prints one as JSON so that it can be
// copied, edited and passed back with `rheo simulate --scenario FILE`.
#include <iostream>
#include <memory>
#include <string>

#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/scenarios/builtin.hpp"

namespace rheo::cli {

namespace {

// The first sentence of a description, for the one-line listing.
std::string first_sentence(const std::string& text) {
  const std::size_t end = text.find(". ");
  return end == std::string::npos ? text : text.substr(0, end + 1);
}

void run_scenarios(const std::string& show) {
  if (!show.empty()) {
    const std::string* text = find_builtin_scenario_text(show);
    if (!text) throw Error("no built-in scenario named \"" + show + "\" (see `rheo scenarios`)");
    std::cout << *text;
    return;
  }
  for (const std::string& name : builtin_scenarios()) {
    const Scenario s = load_scenario(name);
    std::cout << name << ": " << first_sentence(s.description) << "\n";
  }
  std::cout << "\nPrint one as JSON (to copy and edit): rheo scenarios --show NAME\n";
}

}  // namespace

void register_scenarios(CLI::App& app) {
  auto show = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "scenarios",
      "List the built-in scenarios, or print one as JSON (--show NAME): a starting point for "
      "your own scenario file.");
  cmd->add_option("--show", *show, "print the JSON of this built-in scenario")
      ->check(non_empty_name("a built-in scenario's name", "NAME"));
  cmd->callback([show]() { run_scenarios(*show); });
}

}  // namespace rheo::cli
