// The tool's answer at a pose.
//  1. The broad phase: the query's within_reach(centre, reach); out of reach, no contact.
//  2. The segments handle -> point in model units (the pose's rotation and translation) and
//     one query_many() call for all of them.
//  3. The resolution (resolve_tool_contacts): each touching point's depth along its normal,
//     p_i = |f_i| / (k m), and normal n_i; the smallest t with n_i . t >= p_i by coordinate
//     ascent on the dual (Hildreth's method: a multiplier per point, deepest points first, so a
//     plane is resolved in one sweep); when the constraints cannot all hold (a pinch) the least
//     squares t of n_i . t = p_i over the touching points. Force k m t; torque the force at the
//     centre of pressure.
#include "tool/tool_contact.h"
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace hb {
namespace {

constexpr int kMaxSweeps = 64;
constexpr float kResolved = 1e-4f;   // violation left, fraction of the deepest depth
constexpr float kPinched = 1e-2f;    // violation that means no translation frees every point

// The least-squares translation of n_i . t = p_i over the touching points (directions the
// normals do not constrain get none).
Vec3 least_squares_translation(const std::vector<float>& depth, const std::vector<Vec3>& normal, std::size_t n) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d ni = normal[i].cast<double>();
    a += ni * ni.transpose();
    b += double(depth[i]) * ni;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(a);
  const Eigen::Vector3d values = eig.eigenvalues();
  const double floor = 1e-3 * std::max(values.maxCoeff(), 1e-30);
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (values[k] > floor) {
      const Eigen::Vector3d v = eig.eigenvectors().col(k);
      t += v * (v.dot(b) / values[k]);
    }
  return t.cast<float>();
}

} // namespace

ToolProbe::ToolProbe(const ToolShape& shape, double metres_per_unit)
    : shape_(shape), metres_per_unit_(metres_per_unit) {
  const float to_model = float(1.0 / metres_per_unit);
  for (std::size_t i = 0; i < shape.size(); ++i) {
    points_.push_back(shape.points[i] * to_model);
    handles_.push_back(shape.handles[i] * to_model);
    reach_ = std::max({reach_, points_.back().norm(), handles_.back().norm()});
  }
  segments_.resize(points_.size());
  contacts_.resize(points_.size());
  depth_.reserve(points_.size());
  normal_.reserve(points_.size());
  lambda_.reserve(points_.size());
  order_.reserve(points_.size());
  lift_.assign(points_.size(), 0.f);
  star_ = !handles_.empty() && std::all_of(handles_.begin(), handles_.end(), [](const Vec3& h) { return h == Vec3::Zero(); });
  tips_.resize(points_.size());
  if (star_) {
    star_scratch_.segments.reserve(points_.size());
    star_scratch_.order.reserve(points_.size());
    star_scratch_.counts.reserve(points_.size() + 1);
    star_scratch_.directions.reserve(3 * points_.size());
  }
  sag_ = float(shape.sag_m / metres_per_unit);
}

void ToolProbe::segments(const ToolPose& pose, Segment* out) const noexcept {
  const Eigen::Matrix3f r = pose.orientation.normalized().toRotationMatrix();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    out[i].start = pose.position + r * handles_[i];
    out[i].end = pose.position + r * points_[i];
  }
}

ToolAnswer ToolProbe::answer(const ContactQuery& query, const ToolPose& pose, const ForceLaw& law) noexcept {
  asked_ = query.within_reach(pose.position, reach_);
  if (!asked_) {
    ToolAnswer none;
    none.reached = false;
    return none;
  }
  segments(pose, segments_.data());
  if (star_) {
    for (std::size_t i = 0; i < segments_.size(); ++i) tips_[i] = segments_[i].end;
    query.query_star(pose.position, tips_.data(), tips_.size(), law, contacts_.data(), star_scratch_);
  } else {
    query.query_many(segments_.data(), segments_.size(), law, contacts_.data());
  }
  const float* lift = nullptr;
  if (sag_ > 0.f) {
    // The tool's true surface beyond each touching point, along the contact's -n (tool frame).
    const Eigen::Quaternionf to_tool = pose.orientation.normalized().conjugate();
    const float to_model = float(1.0 / metres_per_unit_);
    for (std::size_t i = 0; i < contacts_.size(); ++i) {
      const Contact& c = contacts_[i];
      if (!c.contact || !(c.force.squaredNorm() > 0.f)) continue;
      const Vec3 u = to_tool * Vec3(-c.force.normalized());
      const float gap = float(tool_support(shape_, u)) * to_model - u.dot(points_[i]);
      lift_[i] = std::min(sag_, std::max(0.f, gap));
    }
    lift = lift_.data();
  }
  return resolve_tool_contacts(contacts_.data(), contacts_.size(), pose.position, law, lift, depth_, normal_, lambda_,
                               order_);
}

ToolAnswer resolve_tool_contacts(const Contact* contacts, std::size_t count, const Vec3& centre, const ForceLaw& law,
                                 const float* lift, std::vector<float>& depth, std::vector<Vec3>& normal,
                                 std::vector<float>& lambda, std::vector<std::uint32_t>& order) {
  ToolAnswer out;
  const double k_m = double(law.stiffness_n_per_m) * double(law.metres_per_unit);  // N per model unit
  depth.clear();
  normal.clear();
  order.clear();
  Vec3 pressure = Vec3::Zero(), moment = Vec3::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Contact& c = contacts[i];
    if (!c.contact) continue;
    ++out.contacts;
    const float f = c.force.norm();
    if (!(f > 0.f) || !std::isfinite(f)) continue;
    const float p = float(double(f) / k_m) + (lift ? lift[i] : 0.f);
    const Vec3 n = c.force / f;
    order.push_back(std::uint32_t(depth.size()));
    depth.push_back(p);
    normal.push_back(n);
    pressure += p * n;
    moment += (c.point - centre).cross(p * n);
  }
  const std::size_t n = depth.size();
  if (n == 0) return out;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return depth[a] > depth[b]; });
  lambda.assign(n, 0.f);
  const float deepest = depth[order[0]];
  out.deepest = deepest;
  Vec3 t = Vec3::Zero();
  float worst = 0.f;
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    worst = 0.f;
    for (std::uint32_t i : order) {
      const float v = depth[i] - normal[i].dot(t);
      worst = std::max(worst, v);
      const float step = std::max(-lambda[i], v);
      if (step == 0.f) continue;
      lambda[i] += step;
      t += step * normal[i];
    }
    if (worst <= kResolved * deepest) break;
  }
  // The sweep that ended measured the violation before its own steps: measure it as it stands.
  worst = 0.f;
  for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, depth[i] - normal[i].dot(t));
  if (worst > kPinched * deepest) {
    out.pinched = true;
    t = least_squares_translation(depth, normal, n);
  }
  out.translation = t;
  out.force = (t.cast<double>() * k_m).cast<float>();
  const float g = pressure.norm(), fn = out.force.norm();
  if (g > 0.f && fn > 0.f)
    out.torque = (moment.cast<double>() * (double(fn) / double(g)) * double(law.metres_per_unit)).cast<float>();
  return out;
}

} // namespace hb
