// Minimal entry point for the device branch; the lead's cli/main.cpp replaces it on merge.
#include "commands.h"
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"hapticbox: haptic rendering via directional sampling"};
  app.require_subcommand(1);
  add_devices_command(app);
  add_servo_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hapticbox: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
