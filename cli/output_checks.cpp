#include "output_checks.h"
#include "cli_support.h"
#include "errors.h"
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace hb::cli {

void check_output_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(path + ": is a folder, not an output file");
  const fs::path parent = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(parent, ec)) throw IoError(path + ": cannot write (no folder " + parent.string() + ")");
  // Only rank 0 writes the output, so only rank 0 looks. An existing file is opened for append
  // (its bytes untouched); a new one is tried under a name of this process's own, so the output
  // path never exists before the command has written it, whatever ends the job meanwhile.
  if (!communicator().is_root()) return;
  if (fs::exists(path, ec)) {
    std::ofstream probe(path, std::ios::app | std::ios::binary);
    if (!probe) throw IoError(path + ": cannot write (" + std::strerror(errno) + ")");
    return;
  }
  const std::string trial = path + ".write-check-" + std::to_string(::getpid());
  {
    std::ofstream probe(trial, std::ios::binary);
    if (!probe) throw IoError(path + ": cannot write (" + std::strerror(errno) + ")");
  }
  fs::remove(trial, ec);
}

void check_output_folder(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec)) throw IoError(path + ": is a file, not an output folder");
  fs::create_directories(path, ec);
  if (ec) throw IoError(path + ": cannot create the folder (" + ec.message() + ")");
  const fs::path probe = fs::path(path) / ".hapticbox-write-check";
  {
    std::ofstream out(probe);
    if (!out) throw IoError(path + ": cannot write in the folder (" + std::strerror(errno) + ")");
  }
  fs::remove(probe, ec);
}

} // namespace hb::cli
