#pragma once
// The stability suite run through the servo's own force path: the tick filter of T6/T8 (energy
// guard, then safety) and the suite's default options, one definition for `hapticbox
// stability`, `hapticbox report --stability` and the window's Stability tab.
#include "device/safety.h"
#include "evaluation/stability_suite.h"
#include <cstddef>
#include <string>

namespace hb {

class BoxScene;

/// A factory of hb::SafetyTickFilter for `device`: the given fault response, the energy guard
/// on or off, ticking at the profile's period.
TickFilterFactory safety_tick_filter_factory(const DeviceProfile& device, FaultResponse response, bool energy_guard);

/// `hapticbox stability`'s defaults for `scene`: the Falcon profile, `sites` trajectories per
/// test, the generated objects refined as the scene is, the safety filter with hold-and-ramp
/// and no energy guard.
StabilityOptions default_stability_options(const BoxScene& scene, const std::string& model_name, std::size_t sites);

} // namespace hb
