#include "terminal_progress.h"
#include "cli_support.h"
#include "figure_text.h"
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <unistd.h>

namespace hb::cli {

std::string progress_eta_text(double elapsed, double fraction) {
  // Padded to one width: the line is redrawn in place, a shorter text would leave a tail.
  std::string text;
  if (fraction >= 1.0) {
    text = "done in " + duration_text(elapsed);
  } else if (fraction < 0.01 || elapsed < 1.0) {
    text = duration_text(elapsed) + " elapsed";  // too early for a fair estimate
  } else {
    const double left = elapsed * (1.0 - fraction) / fraction;
    text = duration_text(elapsed) + " elapsed, ETA " + (left < 60.0 ? duration_text(left)
                                                                 : std::to_string(int(left / 60.0)) + " min " +
                                                                       std::to_string(int(left) % 60) + " s");
  }
  if (text.size() < 36) text.append(36 - text.size(), ' ');
  return text;
}

ProgressCallback terminal_progress(const std::string& label) {
  if (!isatty(STDERR_FILENO) || !communicator().is_root()) return {};
  // The clock starts at the first report: a bar made before other work (a bake's, made before
  // the decomposition runs) does not count that work in its rate.
  auto start = std::make_shared<std::optional<std::chrono::steady_clock::time_point>>();
  return [label, start](double fraction) {
    if (!*start) *start = std::chrono::steady_clock::now();
    const int width = 40;
    fraction = std::min(1.0, std::max(0.0, fraction));
    const int filled = int(fraction * width + 0.5);
    std::fprintf(stderr, "\r%s [%s%s] %3d%% %s", label.c_str(), std::string(std::size_t(filled), '#').c_str(),
                 std::string(std::size_t(width - filled), '.').c_str(), int(fraction * 100.0 + 0.5),
                 progress_eta_text(std::chrono::duration<double>(std::chrono::steady_clock::now() - **start).count(), fraction)
                     .c_str());
    if (fraction >= 1.0) std::fprintf(stderr, "\n");
    std::fflush(stderr);
    return true;
  };
}

void clear_progress_line() {
  if (!isatty(STDERR_FILENO) || !communicator().is_root()) return;
  std::fputs("\r\033[K", stderr);  // back to the line's start, erase it: the bar is drawn again at its next report
  std::fflush(stderr);
}

} // namespace hb::cli
