#pragma once
// Checks, before any long work, that a command's output file or folder can be written.
#include <string>

namespace hb::cli {

/// Checks, before any long work, that the output file `path` can be written: opens it for
/// appending (creating it, then removing it again when it did not exist). Throws hb::IoError
/// naming the path and the cause (no such folder, a folder, permission, read-only).
void check_output_file(const std::string& path);
/// The same for an output folder: creates it if needed and writes and removes a probe file.
void check_output_folder(const std::string& path);

} // namespace hb::cli
