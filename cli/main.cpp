// hapticbox: the command-line front end. Parses arguments and calls the layers; holds no
// algorithm. Exit codes: 0 success, 2 usage, 1 failure (message on stderr names the file
// and the cause). Runs with no display.
//
// One binary, with or without MPI: started by mpirun/mpiexec/srun it joins the job's ranks
// (hb::mpi), and the commands that split their work (bake, sweep, eval, field, report) share
// it; alone it is a plain process. Under MPI only rank 0 prints to standard output and writes
// files, and a rank that fails ends the whole job with a message naming the rank.
#include "cli_support.h"
#include "commands.h"
#include "errors.h"
#include "mpi_communicator.h"
#include "option_typos.h"
#include "parallel/huge_pages.h"
#include "parallel/thread_limit.h"
#include <algorithm>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <thread>

namespace {

// The sub-commands whose work is split across ranks; the others refuse to run on several
// ranks (each rank would do the whole job and write the same files). A new command joins this
// list once its core function splits its work (stability does not yet).
const std::set<std::string> kDistributed = {"bake", "sweep", "eval", "field", "report", "stability"};

// The first argument naming a sub-command (main's options come before it).
std::string subcommand_of(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      if (sub->get_name() == argv[i]) return argv[i];
  return "";
}

bool is_command(const CLI::App& app, const std::string& word) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->get_name() == word) return true;
  return false;
}

std::string command_list(const CLI::App& app) {
  std::string out;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    out += (out.empty() ? "" : ", ") + sub->get_name();
  return out;
}

// The first argument that is neither an option of main nor an option's value.
std::string first_word(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads") {
      ++i;  // its value
      continue;
    }
    if (!a.empty() && a[0] == '-') continue;
    return a;
  }
  return "";
}

} // namespace

int main(int argc, char** argv) {
  hb::use_huge_page_heap(argc, argv);  // may re-execute this program once (parallel/huge_pages.h)
  std::unique_ptr<hb::Communicator> comm;
  try {
    comm = hb::mpi::start(&argc, &argv);
  } catch (const std::exception& e) {
    std::cerr << "hapticbox: error: cannot join the MPI job: " << e.what() << "\n";
    return 1;
  }
  hb::cli::set_communicator(comm.get());
  hb::cli::set_command_line(argc, argv);
  const int rank = comm->rank(), ranks = comm->size();
  // Only rank 0 speaks on standard output (progress and --json included).
  if (rank != 0) std::cout.rdbuf(nullptr);
  auto fail = [&](const std::string& what, int code) {
    if (ranks == 1) {
      std::cerr << "hapticbox: " << what << "\n";
      return code;
    }
    comm->abort("hapticbox: rank " + std::to_string(rank) + " of " + std::to_string(ranks) + ": " + what, code);
    return code;  // not reached: abort ends the job
  };

  CLI::App app{"HapticBox: haptic rendering via directional sampling"};
  // What the heap got is read only when asked (a /sys read at every start otherwise).
  app.set_version_flag("--version", [] { return std::string("hapticbox ") + HB_VERSION + " (heap: " + hb::heap_pages() + ")"; });
  app.require_subcommand(1);
  {
    std::string names;
    for (const auto& n : hb::cli::measurement_names()) names += (names.empty() ? "" : ", ") + n;
    app.footer("Measurement-only switches (before/after figures, not options): HB_MEASURE=name[=value],... "
               "in the environment, names: " + names + ". Reader limits: HB_READER_TIMEOUT_S, HB_READER_MEMORY_MB.");
  }
  // Threads per process: by default all cores, shared among the ranks on one node.
  std::optional<hb::ThreadLimit> threads;
  int local_ranks = 1;
  if (const auto* mpi = dynamic_cast<const hb::mpi::MpiCommunicator*>(comm.get())) local_ranks = mpi->local_size();
  if (local_ranks > 1) threads.emplace(std::max(1, int(std::thread::hardware_concurrency()) / local_ranks));
  app.add_option_function<int>(
         "--threads", [&](int t) { threads.emplace(t); },
         "Threads per process (default: the cores, divided among the MPI ranks of a node)")
      ->check(CLI::Range(1, 4096));
  add_info_command(app);
  add_bake_command(app);
  add_query_command(app);
  add_eval_command(app);
  add_bench_command(app);
  add_subdivide_command(app);
  add_simplify_command(app);
  add_devices_command(app);
  add_servo_command(app);
  add_decompose_command(app);
#ifdef HB_WITH_VTK
  add_sweep_command(app);
  add_report_command(app);
  add_field_command(app);
  add_trajectory_command(app);
#endif
  add_compress_command(app);
  add_compress_sweep_command(app);
  add_cache_command(app);
  add_stability_command(app);
  // The first word that is not an option must be a command: say which word was not one, and
  // list the commands (CLI11 alone says "A subcommand is required").
  if (const std::string word = first_word(argc, argv); !word.empty() && !is_command(app, word)) {
    if (rank == 0)
      std::cerr << "hapticbox: unknown command '" << word << "'; the commands are: " << command_list(app)
                << "\n(hapticbox --help describes them; hapticbox COMMAND --help, one)\n";
    return 2;
  }
  // A misspelt option is named with the nearest real one (CLI11 would report a required
  // option missing, or the misspelt one's value as an extra argument).
  if (const std::string typo = hb::cli::unknown_option_message(app, subcommand_of(app, argc, argv), argc, argv);
      !typo.empty()) {
    if (rank == 0) std::cerr << "hapticbox: " << typo << "\n";
    return 2;
  }
  if (ranks > 1) {
    const std::string sub = subcommand_of(app, argc, argv);
    if (!sub.empty() && !kDistributed.count(sub))
      return fail("`" + sub + "` does not split its work across MPI ranks; run it without mpirun (" +
                      std::to_string(ranks) + " ranks)",
                  2);
  }
  try {
    hb::cli::check_measurements();
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Every rank parses the same arguments and fails alike: rank 0 tells, all exit.
    std::ostream null_stream(nullptr);
    const int code = rank == 0 ? app.exit(e) : app.exit(e, null_stream, null_stream);
    return code == 0 ? 0 : 2;
  } catch (const hb::cli::UsageError& e) {
    return fail(e.what(), 2);
  } catch (const std::exception& e) {
    return fail(std::string("error: ") + e.what(), 1);
  }
  return 0;
}
