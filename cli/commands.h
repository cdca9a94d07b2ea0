#pragma once
// The hapticbox command: one file per sub-command, each registering itself on the app.
#include <CLI/CLI.hpp>

void add_info_command(CLI::App& app);
void add_bake_command(CLI::App& app);
void add_query_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_compress_sweep_command(CLI::App& app);
void add_compress_command(CLI::App& app);
