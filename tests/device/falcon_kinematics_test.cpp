#include "device/falcon/falcon_kinematics.h"
#include <gtest/gtest.h>
#include <random>

using namespace hb;

namespace {
std::vector<Vec3d> workspace_points(int n) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-0.04, 0.04);
  std::vector<Vec3d> pts{Vec3d::Zero()};
  while (static_cast<int>(pts.size()) < n) {
    const Vec3d p(u(rng), u(rng), u(rng));
    if (p.norm() <= 0.04) pts.push_back(p);
  }
  return pts;
}
} // namespace

TEST(FalconKinematicsTest, InverseThenForwardReturnsThePointOverTheWorkspace) {
  FalconKinematics k;
  for (const Vec3d& p : workspace_points(2000)) {
    Vec3d theta, back;
    ASSERT_TRUE(k.inverse(p, theta)) << p.transpose();
    ASSERT_TRUE(k.forward(theta, Vec3d::Zero(), back)) << p.transpose();
    EXPECT_LT((back - p).norm(), 1e-6) << p.transpose();
  }
}

TEST(FalconKinematicsTest, JacobianMatchesFiniteDifferences) {
  FalconKinematics k;
  const double h = 1e-6;
  for (const Vec3d& p : workspace_points(200)) {
    Vec3d theta;
    ASSERT_TRUE(k.inverse(p, theta));
    Mat3d J;
    ASSERT_TRUE(k.jacobian(p, theta, J));
    for (int j = 0; j < 3; ++j) {
      Vec3d tp = theta, tm = theta, pp, pm;
      tp[j] += h;
      tm[j] -= h;
      ASSERT_TRUE(k.forward(tp, p, pp));
      ASSERT_TRUE(k.forward(tm, p, pm));
      const Vec3d fd = (pp - pm) / (2 * h);
      EXPECT_LT((fd - J.col(j)).norm(), 1e-5 * (1.0 + J.col(j).norm())) << p.transpose();
    }
  }
}

TEST(FalconKinematicsTest, MotorTorquesDoTheSameWorkAsTheForce) {
  FalconGeometry g;
  g.counts_per_newton_metre = 1.0;  // counts = torque; small forces stay under the cap
  FalconKinematics k(g);
  const Vec3d p(0.01, -0.005, 0.02), f(0.0, 0.0, 2000.0);
  Vec3d theta;
  ASSERT_TRUE(k.inverse(p, theta));
  Mat3d J;
  ASSERT_TRUE(k.jacobian(p, theta, J));
  const auto m = k.force_to_motor(f, p, theta);
  const Vec3d tau = J.transpose() * f;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(m[i], tau[i], 0.5);
}

TEST(FalconKinematicsTest, MotorCommandsAreCappedAndNanGivesZero) {
  FalconKinematics k;
  Vec3d theta;
  ASSERT_TRUE(k.inverse(Vec3d::Zero(), theta));
  for (std::int16_t m : k.force_to_motor(Vec3d(1e6, -1e6, 1e6), Vec3d::Zero(), theta)) {
    EXPECT_LE(m, 4096);
    EXPECT_GE(m, -4096);
  }
  const auto z = k.force_to_motor(Vec3d(std::nan(""), 0, 0), Vec3d::Zero(), theta);
  EXPECT_EQ(z, (std::array<std::int16_t, 3>{0, 0, 0}));
}

TEST(FalconKinematicsTest, EncoderCountsRoundTrip) {
  FalconKinematics k;
  const std::array<std::int16_t, 3> c{-1200, 0, 987};
  EXPECT_EQ(k.theta_to_encoder(k.encoder_to_theta(c)), c);
}

TEST(FalconKinematicsTest, UnreachablePointIsRefused) {
  FalconKinematics k;
  Vec3d theta(1, 2, 3);
  EXPECT_FALSE(k.inverse(Vec3d(0, 0, 1.0), theta));
  EXPECT_EQ(theta, Vec3d(1, 2, 3));
}
