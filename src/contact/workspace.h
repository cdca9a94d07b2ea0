#pragma once
// The one physical scale every figure is judged at: how a model is shown on the device (model
// units to the device's metres) with the stiffness and force limit that go with it. `eval`,
// `bench`, `report`, `field`, `sweep`, `compress-sweep`, the bake's budget, `stability`,
// `servo` and the window all compute forces through Workspace::law(), so the same segment on
// the same model gives the same newtons whichever command is asked.
#include "contact/contact.h"
#include "contact/workspace_options.h"
#include "geometry/segment.h"
#include "math/bounds.h"
#include "math/vec3.h"
#include <string>

namespace hb {

/// The scale a model is judged and rendered at, and the one map between the model and the
/// device: device = (model - model_origin) * metres_per_unit (device metres, origin at the
/// workspace centre). Every front end (the commands, the servo loop, the window, the stability
/// suite, the filters) takes the model to the device and back through it, and its law().
struct Workspace {
  WorkspaceFit fit = WorkspaceFit::device;
  double metres_per_unit = 1e-3;       ///< model units to device metres.
  double stiffness_n_per_m = WorkspaceOptions::kDefaultStiffness;
  double max_force_n = WorkspaceOptions::kDefaultMaxForce;
  double model_diagonal = 0.0;         ///< the model's bounding-box diagonal, model units.
  Vec3 model_origin{Vec3::Zero()};     ///< the model point at the device origin (its box's centre).
  /// The probe of a 3-DOF device, which has no stylus orientation: a virtual stylus of fixed
  /// direction (unit, handle -> tip, model frame) whose tip is the mapped device position and
  /// whose handle lies probe_length behind it (paper section 5: S -> E).
  Vec3 probe_direction{0.f, 0.f, -1.f};
  float probe_length = 1.f;            ///< model units, > 0: kProbeFraction of the diagonal.

  /// The probe's length as a fraction of the model's diagonal.
  static constexpr double kProbeFraction = 0.1;

  /// The force law of this scale (DepthLaw::normal).
  ForceLaw law() const noexcept;
  /// The model's diagonal at the device, metres.
  double diagonal_m() const noexcept { return model_diagonal * metres_per_unit; }
  /// A device position (m) in the model frame (model units).
  Vec3 to_model(const Vec3d& device_m) const noexcept {
    return model_origin + (device_m / metres_per_unit).cast<float>();
  }
  /// A model point (model units) in device metres.
  Vec3d to_device(const Vec3& model) const noexcept { return (model - model_origin).cast<double>() * metres_per_unit; }
  /// The probe segment at a device position (m): tip at the mapped position, handle
  /// probe_length behind it along probe_direction. The servo loop's tick and the window's
  /// readout both make their segment here.
  Segment probe(const Vec3& device_position_m) const noexcept {
    const Vec3 tip = to_model(device_position_m.cast<double>());
    return Segment{tip - probe_direction * probe_length, tip};
  }
  /// One line: "model fitted to the device (diagonal 80 mm, 1 unit = 0.349 mm), k 1500 N/m,
  /// forces up to 8 N".
  std::string describe() const;
  /// Short name of the fit: "device", "real-size", "scale".
  const char* fit_name() const noexcept;
};

/// Reads the front ends' workspace spec "mm=D|real-size|metres-per-unit=S,stiffness=K,max-force=F"
/// (any subset; `--workspace` on the command line, `workspace=` in Python) into `options` (keys not
/// given keep their value): mm in [1, 4000] (WorkspaceFit::device), real-size a flag
/// (WorkspaceFit::real_size), metres-per-unit in [1e-12, 1e6] (WorkspaceFit::scale), stiffness
/// in [1e-3, 1e5] N/m, max-force in [1e-3, 500] N. Throws hb::InvalidInput naming "--workspace",
/// the key and the bad value, or two of mm, real-size and metres-per-unit given together.
void parse_workspace_spec(const std::string& spec, WorkspaceOptions& options);

/// The workspace of a model whose bounding-box diagonal is `model_diagonal` (model units; the
/// mesh's, or SourceInfo::diagonal for a box file) and whose box is centred at `model_origin`
/// under `options`; the probe is kProbeFraction of the diagonal long (1 unit for an empty
/// model), along -z. Throws hb::InvalidInput naming the value when an option is out of range
/// (diagonal in [1 mm, 4 m], stiffness in (0, 1e5] N/m, force in (0, 500] N, scale > 0) or the
/// diagonal is not positive under WorkspaceFit::device.
Workspace make_workspace(double model_diagonal, const WorkspaceOptions& options = {},
                         const Vec3& model_origin = Vec3::Zero());
/// The workspace of a model with bounding box `model_bounds` (its centre at the device origin).
Workspace make_workspace(const Bounds& model_bounds, const WorkspaceOptions& options = {});

} // namespace hb
