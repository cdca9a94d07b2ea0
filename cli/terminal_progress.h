#pragma once
// The terminal progress bar of a long command: drawn on stderr when it is a terminal, by rank 0
// only, with the elapsed time and an estimate of the time left.
#include "progress.h"
#include <string>

namespace hb::cli {

/// A progress callback drawing a bar on stderr when it is a terminal (silent otherwise, and
/// on every rank but 0: rank 0 reports for the whole job).
ProgressCallback terminal_progress(const std::string& label);
/// Erases the progress bar's line on a terminal (stderr), so that a line printed now (a table
/// row on stdout) starts at the left margin instead of after the bar; the bar comes back at
/// its next report.
void clear_progress_line();
/// The text after a terminal progress bar: elapsed time and, from 1 % and 1 s on, the time left
/// at the rate so far ("12.3 s elapsed, ETA 41.2 s"; "done in 53.5 s" at the end).
std::string progress_eta_text(double elapsed_seconds, double fraction);

} // namespace hb::cli
