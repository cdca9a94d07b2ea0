#include "device/stability_defaults.h"
#include "device/safety_tick_filter.h"
#include "haptic_box/box_scene.h"
#include <memory>

hb::TickFilterFactory hb::safety_tick_filter_factory(const DeviceProfile& device, FaultResponse response,
                                                     bool energy_guard) {
  SafetyOptions safety;
  safety.fault_response = response;
  EnergyGuardOptions guard;
  guard.enabled = energy_guard;
  const DeviceSpec spec = device_spec_of(device);
  const double dt = device.period_s;
  return [spec, safety, guard, dt] {
    return std::unique_ptr<TickFilter>(new SafetyTickFilter(spec, safety, guard, dt));
  };
}

hb::StabilityOptions hb::default_stability_options(const BoxScene& scene, const std::string& model_name,
                                                   std::size_t sites) {
  StabilityOptions so;
  so.sites = sites;
  so.generated_refine = scene.refines();
  so.model_name = model_name;
  so.filter = safety_tick_filter_factory(so.device, FaultResponse::hold_and_ramp, false);
  so.filter_name = "safety hold-and-ramp";
  return so;
}
