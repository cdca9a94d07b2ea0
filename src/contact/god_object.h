#pragma once
// A proxy (god-object, Zilles and Salisbury 1995) over any segment-query answerer: the box
// scene and exact Embree alike, so that box and exact stay comparable. A penalty law pushes
// along the normal of whichever face the probe answers; in a crisp concave crease that normal
// flips from one wall to the other and the hand chatters (docs/stability.md, T4). The proxy
// is a point kept on the free side of the surface: each tick it moves toward the device tip,
// stopped by up to three constraint planes found by queries from the proxy toward its target,
// and the force is k (proxy - tip). In a crease two planes hold it on the crease line, and the
// force turns smoothly with the tip.
#include "contact/contact.h"
#include <cstdint>
#include <string>

namespace hb {

/// How answers become forces, along a trajectory or in the servo loop (`stability --law`,
/// `servo --law`, ServoOptions::contact_law).
enum class ContactLaw : std::uint8_t {
  penalty,  ///< the force law on each tick's answer (ForceLaw::depth), stateless: the default.
  proxy,    ///< a GodObject over the answers, one per trajectory (per servo loop).
};
/// "penalty" or "proxy".
const char* to_string(ContactLaw law) noexcept;
/// Parses "penalty" or "proxy"; throws hb::InvalidInput naming the value otherwise.
ContactLaw contact_law(const std::string& name);

/// Options of GodObject.
struct GodObjectOptions {
  /// How far in front of each constraint plane the proxy is held, metres (> 0; 0.5 um felt as
  /// 1.5 mN at 3,000 N/m).
  float clearance_m = 0.5e-6f;
  /// Constraint searches per tick at most (each one or two segment queries: the path from
  /// the proxy to its target, then the stylus ending at the target), >= 1.
  int max_queries = 6;
};

/// Counters over the proxy's life (diagnostics: what the solver did).
struct GodObjectStats {
  std::uint64_t ticks = 0, contact_ticks = 0, queries = 0;
  std::uint64_t seeds = 0;      ///< contact episodes begun (proxy put at the stylus's surface point).
  std::uint64_t reseeds = 0;    ///< the proxy found no constraint while the stylus touches: put back.
  std::uint64_t fallbacks = 0;  ///< still none: that tick's penalty answer was used.
  std::uint64_t max_planes = 0; ///< most constraint planes active in one tick.
};

/// The proxy. One per trajectory (it has state); step() is noexcept and allocates nothing.
/// Contact is the project's definition, on the stylus segment (handle -> tip): with no contact
/// there the proxy is free (at the tip) and the force zero, so release, pop-through at the
/// stylus length and the handle-inside rule stay those of the penalty law; only the force
/// of a contact differs. The answer's `depth` is the stylus's depth, `point` the proxy,
/// `normal` the surface it rests on (the active planes' normals summed: a crease's bisector
/// when two walls hold it), `force`
/// k (proxy - tip) in N (law.depth is not used: the proxy is the tip's constrained nearest
/// point, so a wall feels k at any tilt).
class GodObject {
public:
  explicit GodObject(const ContactQuery& query, GodObjectOptions options = {}) noexcept
      : query_(&query), options_(options) {}

  /// Forgets the contact: the next contact seeds the proxy afresh.
  void reset() noexcept { in_contact_ = false; }

  /// One tick for the probe segment (handle -> tip, model units).
  Contact step(const Segment& probe, const ForceLaw& law) noexcept;

  const Vec3& proxy() const noexcept { return proxy_; }
  bool in_contact() const noexcept { return in_contact_; }
  /// Constraint planes active at the end of the last tick (0..3).
  int active_planes() const noexcept { return planes_; }
  const GodObjectStats& stats() const noexcept { return stats_; }

private:
  // Moves proxy_ toward `goal`; returns the planes found (0: none, the proxy reached the goal).
  // l, stylus_length: the probe's direction and length (the stylus check of each target).
  int solve(const Vec3& goal, const ForceLaw& law, float clearance, const Vec3& l, float stylus_length) noexcept;

  const ContactQuery* query_;
  GodObjectOptions options_;
  bool in_contact_ = false;
  Vec3 proxy_{Vec3::Zero()};
  Vec3 rest_normal_{Vec3::Zero()};  // the constraint planes' normals, summed, unit
  int planes_ = 0;
  GodObjectStats stats_;
};

/// A ContactQuery that answers through a GodObject: each query() is one tick of the proxy.
/// Stateful, so not for many threads, and one per trajectory. (The servo loop keeps its own
/// GodObjects: ServoOptions::contact_law.)
class GodObjectQuery final : public ContactQuery {
public:
  explicit GodObjectQuery(const ContactQuery& query, GodObjectOptions options = {}) noexcept
      : proxy_(query, options) {}
  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override {
    return proxy_.step(segment, law);
  }
  void reset() noexcept { proxy_.reset(); }
  const GodObject& proxy() const noexcept { return proxy_; }

private:
  mutable GodObject proxy_;
};

} // namespace hb
