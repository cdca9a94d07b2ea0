#pragma once
// Delta-robot kinematics of the Novint Falcon (Clavel-type rotary delta).
//
// Model (self-consistent; constants after libnifalcon's FalconGeometry.h where it gives them,
// simplified to a symmetric delta: verify against hardware before trusting absolute positions):
// - Kinematic frame: z points out of the device towards the user, the three motors sit on a
//   circle of radius `base_radius` in the z = 0 plane at angles phi_i = 105, -15, -135 degrees
//   (libnifalcon: pi/2, -pi/6, -5pi/6, each + 15 degrees). u_i = (cos phi_i, sin phi_i, 0).
// - Arm i turns by theta_i in the plane (u_i, z): knee K_i = B_i + a (cos theta_i u_i +
//   sin theta_i z), with a = 0.060 m; a parallelogram of length b = 0.1025 m joins the knee
//   to the effector joint p + effector_radius u_i.
// - Device frame = kinematic frame shifted by `centre_z` along z, so the workspace sphere of
//   radius 0.04 m is centred on the device origin.
// - Encoders: theta_i = theta_offset + count * 2 pi / 1280 * (shaft diameter / arm drum
//   diameter) = 35 deg + count * 6.36e-4 rad (libnifalcon: 320 slots x4 quadrature,
//   0.01425 m shaft, 0.110 m drum, 35 degree offset).
// - Motor command = torque at the arm (N m) * `counts_per_newton_metre`, capped at +-4096.
//   The torque constant is an assumption (about 4096 counts for the 8 N peak), to calibrate.
#include "math/vec3.h"
#include <Eigen/Core>
#include <array>
#include <cstdint>

namespace hb {

struct FalconGeometry {
  double a = 0.060;               ///< upper arm, m.
  double b = 0.1025;              ///< parallelogram, m.
  double base_radius = 0.037234;  ///< motor axis circle, m.
  double effector_radius = 0.014; ///< effector joint circle, m.
  double centre_z = 0.11;         ///< workspace centre in the kinematic frame, m.
  double theta_offset = 35.0 * 3.14159265358979323846 / 180.0;  ///< angle at encoder 0, rad.
  double rad_per_count = 2.0 * 3.14159265358979323846 / 1280.0 * (0.01425 / 0.110);
  double counts_per_newton_metre = 10000.0;
  std::array<double, 3> phi{1.8325957145940461, -0.26179938779914941, -2.3561944901923448};
};

using Vec3d = Eigen::Vector3d;
using Mat3d = Eigen::Matrix3d;

class FalconKinematics {
public:
  explicit FalconKinematics(FalconGeometry g = {});

  /// Closed-form inverse: device-frame position (m) to arm angles (rad). False when the point
  /// is out of reach (angles unchanged).
  bool inverse(const Vec3d& position_m, Vec3d& theta) const noexcept;

  /// Forward by Newton iteration from `guess` (device frame, m); false when it does not
  /// converge to 1e-12 m within `max_iterations`. noexcept, allocation-free.
  bool forward(const Vec3d& theta, const Vec3d& guess, Vec3d& position_m,
               int max_iterations = 20) const noexcept;

  /// J = d position / d theta at (position, theta), m/rad. False near a singularity.
  bool jacobian(const Vec3d& position_m, const Vec3d& theta, Mat3d& J) const noexcept;

  /// Force (N, device frame) to motor commands through J^T, capped at +-4096.
  std::array<std::int16_t, 3> force_to_motor(const Vec3d& force_n, const Vec3d& position_m,
                                             const Vec3d& theta) const noexcept;

  Vec3d encoder_to_theta(const std::array<std::int16_t, 3>& counts) const noexcept;
  std::array<std::int16_t, 3> theta_to_encoder(const Vec3d& theta) const noexcept;

  const FalconGeometry& geometry() const noexcept { return g_; }

private:
  /// Constraint residuals F_i = |q_i - k_i|^2 - b^2 and their partials.
  void constraints(const Vec3d& p_kin, const Vec3d& theta, Vec3d& F, Mat3d& dF_dp,
                   Vec3d& dF_dtheta) const noexcept;

  FalconGeometry g_;
  std::array<Vec3d, 3> u_;
};

} // namespace hb
