#include "contact/tick_filter.h"
#include "errors.h"

namespace hb {

DeviceProfile falcon_profile() {
  DeviceProfile p;
  p.name = "falcon";
  p.max_force_n = 8.0;
  p.max_stiffness_n_per_m = 3000.0;
  return p;
}

DeviceProfile touch_profile() {
  DeviceProfile p;
  p.name = "touch";
  p.max_force_n = 3.3;
  p.max_stiffness_n_per_m = 400.0;
  return p;
}

DeviceProfile device_profile(const std::string& name) {
  if (name == "falcon") return falcon_profile();
  if (name == "touch") return touch_profile();
  throw InvalidInput("device profile '" + name + "': expected falcon or touch");
}

} // namespace hb
