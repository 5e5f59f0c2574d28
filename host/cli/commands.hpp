// Subcommands of the `rheo` tool; each lives in its own file and registers itself here.
#pragma once

#include <CLI/CLI.hpp>

namespace rheo::cli {

void register_simulate(CLI::App& app);
void register_fit(CLI::App& app);
void register_diagnose(CLI::App& app);
void register_scenarios(CLI::App& app);
void register_synth(CLI::App& app);
void register_cosim(CLI::App& app);
void register_fixed(CLI::App& app);
void register_cosim_server(CLI::App& app);
void register_bench_link(CLI::App& app);
void register_haptic_server(CLI::App& app);

}  // namespace rheo::cli
