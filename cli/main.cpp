// hapticbox: the command-line front end. Parses arguments and calls the layers; holds no
// algorithm. Exit codes: 0 success, 2 usage, 1 failure (message on stderr names the file
// and the cause). Runs with no display.
#include "cli_support.h"
#include "commands.h"
#include "errors.h"
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"HapticBox: haptic rendering via directional sampling"};
  app.set_version_flag("--version", std::string("hapticbox ") + HB_VERSION);
  app.require_subcommand(1);
  add_info_command(app);
  add_bake_command(app);
  add_query_command(app);
  add_eval_command(app);
  add_bench_command(app);
  add_subdivide_command(app);
  add_devices_command(app);
  add_servo_command(app);
  add_decompose_command(app);
#ifdef HB_WITH_VTK
  add_sweep_command(app);
  add_report_command(app);
  add_field_command(app);
#endif
  add_compress_command(app);
  add_compress_sweep_command(app);
  add_cache_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const hb::cli::UsageError& e) {
    std::cerr << "hapticbox: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hapticbox: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
