#pragma once
#include <functional>

namespace hb {

/// Progress callback of long operations: receives the fraction done in [0, 1] and returns
/// false to cancel, in which case the operation throws hb::Cancelled. Called from the
/// calling thread only, at most a few hundred times per operation.
using ProgressCallback = std::function<bool(double fraction)>;

} // namespace hb
