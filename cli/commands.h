#pragma once
// One function per `hapticbox` command; each lives in cli/<name>_command.cpp.
// Commands throw CLI::ValidationError for usage errors (exit 2) and std::exception for
// failures (exit 1, message on stderr naming the file and the cause).
namespace CLI {
class App;
}

void add_devices_command(CLI::App& app);
void add_servo_command(CLI::App& app);
