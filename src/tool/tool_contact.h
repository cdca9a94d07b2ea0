#pragma once
// A tool's answer at one pose: every point of its shell asked as a probe segment (handle ->
// point) of any ContactQuery in one batched call, then the point contacts resolved into one
// net force and torque (docs/tools.md):
//  - the force is the stiffness times the smallest translation t that takes every touching
//    point out of its surface, n_i . t >= p_i (p_i the point's depth along its normal n_i, as
//    the force law measures it, plus how far the tool's true surface reaches past the point
//    along -n_i, at most the shell's sag: on a plane every touching point then gives the
//    tool's own depth). A sphere pressed d into a plane feels k d (its deepest point's
//    depth) whatever the point count, not k times the points touching; a tool pinched between
//    opposite walls (no such t) takes the least-squares t over its touching points, so a
//    centred sphere in a channel feels no lateral force;
//  - the torque about the tool's centre is that force applied at the centre of pressure: the
//    points' r_i x (p_i n_i), scaled by |F| / |sum p_i n_i|.
#include "contact/contact.h"
#include "tool/tool_shape.h"
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace hb {

/// Where the tool is: its centre (model units) and its orientation (tool frame to model frame).
struct ToolPose {
  Vec3 position{Vec3::Zero()};
  Eigen::Quaternionf orientation{Eigen::Quaternionf::Identity()};
};

/// The tool's contact at one pose.
struct ToolAnswer {
  std::uint32_t contacts = 0;   ///< points of the shell in contact.
  Vec3 force{Vec3::Zero()};     ///< N, on the tool.
  Vec3 torque{Vec3::Zero()};    ///< N m, on the tool about its centre.
  /// The translation that resolves the contacts, model units (force = k t metres).
  Vec3 translation{Vec3::Zero()};
  bool pinched = false;         ///< no translation frees every point (least squares taken).
  float deepest = 0.f;          ///< the deepest touching point's depth along its normal, model units.
  bool reached = true;          ///< false: the broad phase found no surface within the tool's reach.
};

/// A tool at a workspace scale, asking a ContactQuery: its shell in model units and the
/// buffers of one tick. One per caller (a servo loop, a trajectory, a thread): answer() writes
/// the buffers and allocates nothing.
class ToolProbe {
public:
  /// `metres_per_unit`: the workspace's scale (Workspace::metres_per_unit).
  ToolProbe(const ToolShape& shape, double metres_per_unit);

  /// The tool's contact at `pose` on `query` by `law` (the same law for every point). When the
  /// query's broad phase (ContactQuery::within_reach) finds no surface within the tool's reach,
  /// no point is asked.
  ToolAnswer answer(const ContactQuery& query, const ToolPose& pose, const ForceLaw& law) noexcept;

  /// The probe segments of `pose`, one a point (handle -> point), into `out` (size() of them).
  void segments(const ToolPose& pose, Segment* out) const noexcept;
  /// The last answer's segments and point contacts (empty when the broad phase skipped them).
  const std::vector<Segment>& last_segments() const noexcept { return segments_; }
  const std::vector<Contact>& last_contacts() const noexcept { return contacts_; }
  bool last_asked() const noexcept { return asked_; }

  std::size_t size() const noexcept { return points_.size(); }
  /// The largest distance from the centre of a point or handle, model units.
  float reach() const noexcept { return reach_; }
  double metres_per_unit() const noexcept { return metres_per_unit_; }
  const ToolShape& shape() const noexcept { return shape_; }

private:
  ToolShape shape_;
  double metres_per_unit_;
  std::vector<Vec3> points_, handles_;  // model units, tool frame
  float reach_ = 0.f;
  std::vector<Segment> segments_;
  std::vector<Contact> contacts_;
  bool asked_ = false;
  // Scratch of the resolution.
  std::vector<float> depth_, lambda_;
  std::vector<Vec3> normal_;
  std::vector<std::uint32_t> order_;
  std::vector<float> lift_;
  float sag_ = 0.f;  // model units
  // Every handle at the centre (a sphere): the points are asked as segments from one handle
  // (ContactQuery::query_star), which a scene answers with a broad phase of its own.
  bool star_ = false;
  std::vector<Vec3> tips_;
  StarScratch star_scratch_;
};

/// Resolves point contacts (contacts[i] the answer to the segment of the tool's point i) into
/// the tool's net force and torque about `centre` (model units), as above. `lift`, when not
/// null, adds lift[i] (model units) to point i's depth: how far the tool's true surface reaches
/// beyond the point towards the surface (ToolProbe: at most the shell's sag, so that the
/// deepest point stands for the tool's deepest surface, whatever the point count).
/// `depth`, `normal`, `lambda`, `order` are scratch (resized). noexcept apart from the
/// scratch's growth.
ToolAnswer resolve_tool_contacts(const Contact* contacts, std::size_t count, const Vec3& centre, const ForceLaw& law,
                                 const float* lift, std::vector<float>& depth, std::vector<Vec3>& normal,
                                 std::vector<float>& lambda, std::vector<std::uint32_t>& order);

} // namespace hb
