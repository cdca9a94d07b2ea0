#include "device/safety_tick_filter.h"
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

void hb::use_servo_force_path(TickFilterFactory& filter, std::string& filter_name, const DeviceProfile& device) {
  filter = safety_tick_filter_factory(device, FaultResponse::hold_and_ramp, false);
  filter_name = "safety hold-and-ramp";
}
