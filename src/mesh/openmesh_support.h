#pragma once
// What the OM reader and the writers that go through OpenMesh share: one OpenMesh call at a
// time (its log streams are process-global) and its std::cerr chatter captured as text.
// Internal to src/mesh.
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

namespace hb::detail {

/// OpenMesh's log streams are process-global: hold this around any OpenMesh IO call.
std::mutex& openmesh_mutex();

/// While alive, routes omerr() into a string instead of std::cerr and mutes omout()/omlog();
/// restores the previous state on destruction. Hold openmesh_mutex() around it.
class OpenMeshChatterCapture {
public:
  OpenMeshChatterCapture();
  ~OpenMeshChatterCapture();
  OpenMeshChatterCapture(const OpenMeshChatterCapture&) = delete;
  OpenMeshChatterCapture& operator=(const OpenMeshChatterCapture&) = delete;

  /// Distinct non-empty lines written so far, with a repeat count.
  std::vector<std::string> lines();

private:
  std::ostringstream captured_;
  bool had_cerr_ = false;
  bool err_was_enabled_ = true, out_was_enabled_ = true, log_was_enabled_ = true;
};

} // namespace hb::detail
