// Falcon delta kinematics.
// 1. Inverse (closed form): with q_i = p + (r_e - r_b) u_i, the leg constraint
//    |q_i - a (cos t u_i + sin t z)|^2 = b^2 reduces to A cos t + C sin t = K with
//    A = q_i.u_i, C = q_i.z, K = (|q_i|^2 + a^2 - b^2) / (2a); the elbow-out root is
//    t = atan2(C, A) - acos(K / hypot(A, C)).
// 2. Forward: Newton on the three constraints in p (3x3 solve per step).
// 3. Jacobian: implicit differentiation, dp/dtheta = -(dF/dp)^-1 diag(dF_i/dtheta_i).
// 4. Motor torques: tau = J^T F (virtual work), scaled to counts and capped.
#include "device/falcon/falcon_kinematics.h"
#include "device/falcon/falcon_packet.h"
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace hb {

FalconKinematics::FalconKinematics(FalconGeometry g) : g_(g) {
  for (int i = 0; i < 3; ++i) u_[i] = Vec3d(std::cos(g_.phi[i]), std::sin(g_.phi[i]), 0.0);
}

bool FalconKinematics::inverse(const Vec3d& p, Vec3d& theta) const noexcept {
  const Vec3d pk = p + Vec3d(0, 0, g_.centre_z);
  Vec3d t;
  for (int i = 0; i < 3; ++i) {
    const Vec3d q = pk + (g_.effector_radius - g_.base_radius) * u_[i];
    const double A = q.dot(u_[i]), C = q.z();
    const double K = (q.squaredNorm() + g_.a * g_.a - g_.b * g_.b) / (2.0 * g_.a);
    const double R = std::hypot(A, C);
    if (!(R > 1e-12) || std::abs(K) > R) return false;
    t[i] = std::atan2(C, A) - std::acos(K / R);
  }
  theta = t;
  return true;
}

void FalconKinematics::constraints(const Vec3d& pk, const Vec3d& theta, Vec3d& F, Mat3d& dF_dp,
                                   Vec3d& dF_dtheta) const noexcept {
  const Vec3d z(0, 0, 1);
  for (int i = 0; i < 3; ++i) {
    const Vec3d q = pk + (g_.effector_radius - g_.base_radius) * u_[i];
    const Vec3d k = g_.a * (std::cos(theta[i]) * u_[i] + std::sin(theta[i]) * z);
    const Vec3d dk = g_.a * (-std::sin(theta[i]) * u_[i] + std::cos(theta[i]) * z);
    const Vec3d d = q - k;
    F[i] = d.squaredNorm() - g_.b * g_.b;
    dF_dp.row(i) = 2.0 * d.transpose();
    dF_dtheta[i] = -2.0 * d.dot(dk);
  }
}

bool FalconKinematics::forward(const Vec3d& theta, const Vec3d& guess, Vec3d& position_m,
                               int max_iterations) const noexcept {
  Vec3d pk = guess + Vec3d(0, 0, g_.centre_z);
  Vec3d F, dFt;
  Mat3d dFp;
  for (int it = 0; it < max_iterations; ++it) {
    constraints(pk, theta, F, dFp, dFt);
    Eigen::PartialPivLU<Mat3d> lu(dFp);
    if (!(std::abs(lu.determinant()) > 1e-18)) return false;
    const Vec3d step = lu.solve(F);
    if (!step.allFinite()) return false;
    pk -= step;
    if (step.norm() < 1e-12) {
      position_m = pk - Vec3d(0, 0, g_.centre_z);
      return true;
    }
  }
  return false;
}

bool FalconKinematics::jacobian(const Vec3d& p, const Vec3d& theta, Mat3d& J) const noexcept {
  Vec3d F, dFt;
  Mat3d dFp;
  constraints(p + Vec3d(0, 0, g_.centre_z), theta, F, dFp, dFt);
  Eigen::PartialPivLU<Mat3d> lu(dFp);
  if (!(std::abs(lu.determinant()) > 1e-18)) return false;
  J = -lu.solve(Mat3d(dFt.asDiagonal()));
  return J.allFinite();
}

std::array<std::int16_t, 3> FalconKinematics::force_to_motor(const Vec3d& f, const Vec3d& p,
                                                             const Vec3d& theta) const noexcept {
  std::array<std::int16_t, 3> out{0, 0, 0};
  Mat3d J;
  if (!f.allFinite() || !jacobian(p, theta, J)) return out;
  const Vec3d tau = J.transpose() * f;
  for (int i = 0; i < 3; ++i) {
    const double c = std::clamp(tau[i] * g_.counts_per_newton_metre,
                                -double(falcon_motor_limit), double(falcon_motor_limit));
    out[i] = static_cast<std::int16_t>(std::lround(c));
  }
  return out;
}

Vec3d FalconKinematics::encoder_to_theta(const std::array<std::int16_t, 3>& c) const noexcept {
  return Vec3d(g_.theta_offset + c[0] * g_.rad_per_count, g_.theta_offset + c[1] * g_.rad_per_count,
               g_.theta_offset + c[2] * g_.rad_per_count);
}

std::array<std::int16_t, 3> FalconKinematics::theta_to_encoder(const Vec3d& t) const noexcept {
  std::array<std::int16_t, 3> c{};
  for (int i = 0; i < 3; ++i)
    c[i] = static_cast<std::int16_t>(std::clamp<long>(
        std::lround((t[i] - g_.theta_offset) / g_.rad_per_count), -32768, 32767));
  return c;
}

} // namespace hb
