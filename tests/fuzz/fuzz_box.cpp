// libFuzzer target: the box file loader plus queries.
//
//  1. The first input byte chooses the load mode (bit 0: LoadOptions::verify); the rest is
//     the file. Random bytes almost never pass the header checksum, which would leave every
//     field behind it untested, so the target re-signs the header (and, in verify mode, the
//     table, id and surface hashes) where the layout parses: what is fuzzed is every value
//     the checksums protect, as a file corrupted before it was signed would carry them
//     (the hashes checked on every load, piece ids, scene grid, budget report, normal map and
//     stroke mesh, are always re-signed).
//  2. A rejected file must give an hb::Error naming the file.
//  3. An accepted file is queried, every box and the scene (also as one probe with its query
//     state, which a stored stroke mesh answers), with segments through each box
//     (along its axes and between pseudo-random points from the input), long, tiny, huge and
//     NaN segments. Every contact must have a finite point and force, depth in [0, segment
//     length] and a unit normal; query_many must give query()'s answers bit for bit on finite
//     segments; nothing may crash or read out of bounds (the build runs ASan + UBSan).
#include "fuzz_support.h"
#include "store/box_file.h"

#include <xxhash.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace {

/// Walks the header as load_box_file does; re-signs what it finds. Stops where it runs out.
void resign(std::string& f, bool tables) {
  std::size_t pos = 8;
  const auto skip = [&](std::size_t n) {
    if (n > f.size() - pos) return false;
    pos += n;
    return true;
  };
  const auto u32 = [&](std::uint32_t& v) {
    if (4 > f.size() - pos) return false;
    std::memcpy(&v, f.data() + pos, 4);
    pos += 4;
    return true;
  };
  const auto u64 = [&](std::uint64_t& v) {
    if (8 > f.size() - pos) return false;
    std::memcpy(&v, f.data() + pos, 8);
    pos += 8;
    return true;
  };
  if (f.size() < 8) return;
  std::uint32_t version = 0, count = 0, path_len = 0;
  std::uint64_t ignored = 0;
  if (!u32(version) || !u32(count) || !skip(8 + 8 + 4) || !u32(path_len) || !skip(path_len)) return;
  if (count > 64) return;
  struct Hashed {
    std::uint64_t offset, bytes;
    std::size_t hash_at;
    bool always = false;  // checked on every load (piece ids, scene grid), not only with verify
  };
  std::vector<Hashed> sections;
  for (std::uint32_t b = 0; b < count; ++b) {
    Hashed table{};
    if (!skip(4 + 4 + 4 + 12 + 36 + 12) || !u64(table.offset) || !u64(table.bytes)) return;
    table.hash_at = pos;
    if (!u64(ignored)) return;
    sections.push_back(table);
    if (version >= 2 && !skip(20 + 8)) return;
    if (version >= 3) {
      Hashed ids{};
      if (!u64(ids.offset) || !u64(ids.bytes)) return;
      ids.hash_at = pos;
      if (!u64(ignored) || !skip(4)) return;
      sections.push_back(ids);
    }
  }
  // A section's (offset, bytes, hash) triple; `always`: hashed on every load.
  const auto section = [&](bool always) {
    Hashed h{};
    if (!u64(h.offset) || !u64(h.bytes)) return false;
    h.hash_at = pos;
    h.always = always;
    if (!u64(ignored)) return false;
    sections.push_back(h);
    return true;
  };
  if (version >= 3 && !section(false)) return;                 // surface records
  if (version >= 4 && !section(true)) return;                  // piece ids
  if (version >= 5 && !section(true)) return;                  // scene grid
  if (version >= 6 && !section(true)) return;                  // budget report
  if (version >= 7 && (!skip(4) || !section(true))) return;    // normal map (after its side)
  if (version >= 9 && !section(true)) return;                  // stroke mesh
  if (8 > f.size() - pos) return;
  for (const Hashed& s : sections)
    if ((tables || s.always) && s.offset <= f.size() && s.bytes <= f.size() - s.offset) {
      const std::uint64_t h = XXH3_64bits(f.data() + s.offset, s.bytes);
      std::memcpy(&f[s.hash_at], &h, 8);
    }
  const std::uint64_t h = XXH3_64bits(f.data(), pos);
  std::memcpy(&f[pos], &h, 8);
}

void check_contact(const hb::Contact& c, const hb::Segment& s, const char* who) {
  if (!c.contact) {
    if (c.depth != 0.f || !c.force.isZero()) hb::fuzz::fail(std::string(who) + ": a miss with a depth or a force");
    return;
  }
  const float length = (s.end - s.start).norm();
  if (!std::isfinite(c.depth) || c.depth < 0.f || c.depth > length * (1.f + 1e-4f) + 1e-30f)
    hb::fuzz::fail(std::string(who) + ": depth " + std::to_string(c.depth) + " outside [0, " +
                   std::to_string(length) + "]");
  if (!c.point.allFinite() || !c.force.allFinite()) hb::fuzz::fail(std::string(who) + ": non-finite point or force");
  if (!(std::fabs(c.normal.norm() - 1.f) < 1e-3f)) hb::fuzz::fail(std::string(who) + ": normal not of unit length");
}

bool same(const hb::Contact& a, const hb::Contact& b) {
  return a.contact == b.contact && std::memcmp(&a.depth, &b.depth, sizeof a.depth) == 0 &&
         std::memcmp(a.point.data(), b.point.data(), 12) == 0 && std::memcmp(a.normal.data(), b.normal.data(), 12) == 0 &&
         std::memcmp(a.force.data(), b.force.data(), 12) == 0;
}

std::vector<hb::Segment> probes(const hb::Obb& o, std::uint64_t seed) {
  std::vector<hb::Segment> out;
  const float reach = 1.5f * o.diagonal();
  for (int a = 0; a < 3; ++a)
    for (float sign : {-1.f, 1.f}) {
      const hb::Vec3 dir = sign * o.axes.col(a);
      out.push_back({o.center + reach * dir, o.center});                 // handle outside, tip at the centre
      out.push_back({o.center + reach * dir, o.center - reach * dir});   // right through
      out.push_back({o.center + 0.25f * reach * dir, o.center + 0.2f * reach * dir});
    }
  std::uint64_t x = seed | 1;
  const auto next = [&] {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    return float(double(x >> 11) * (1.0 / 9007199254740992.0) * 2.0 - 1.0);
  };
  for (int k = 0; k < 24; ++k) {
    const hb::Vec3 p = o.to_world(hb::Vec3(next(), next(), next()).cwiseProduct(o.half) * 1.4f);
    const hb::Vec3 q = o.to_world(hb::Vec3(next(), next(), next()).cwiseProduct(o.half) * 1.4f);
    out.push_back({p, q});
  }
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  out.push_back({o.center, o.center});                                  // zero length
  out.push_back({o.center, o.center + hb::Vec3(1e-30f, 0.f, 0.f)});      // tiny
  out.push_back({hb::Vec3::Constant(-3e38f), hb::Vec3::Constant(3e38f)});  // huge
  out.push_back({hb::Vec3(1e30f, -1e30f, 1e30f), o.center});
  out.push_back({hb::Vec3(nan, 0.f, 0.f), o.center});
  out.push_back({o.center, hb::Vec3(0.f, inf, 0.f)});
  return out;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool verify = data[0] & 1;
  std::string file(reinterpret_cast<const char*>(data) + 1, size - 1);
  resign(file, verify);
  const std::string path =
      hb::fuzz::write_scratch(".hbox", reinterpret_cast<const std::uint8_t*>(file.data()), file.size());
  hb::LoadOptions options;
  options.verify = verify;
  try {
    const hb::BoxScene scene = hb::load_box_file(path, options);
    const hb::ForceLaw law;
    const std::uint64_t seed = XXH3_64bits(data, size);
    std::size_t boxes = 0;
    const hb::SceneProbe probe(scene);  // a probe's successive queries (the stroke route, when stored)
    for (const hb::HapticBox& box : scene.parts().boxes) {
      if (++boxes > 4) break;
      const std::vector<hb::Segment> segments = probes(box.obb(), seed);
      std::vector<hb::Contact> many(segments.size());
      box.query_many(segments.data(), segments.size(), law, many.data());
      for (std::size_t i = 0; i < segments.size(); ++i) {
        const hb::Contact one = box.query(segments[i], law);
        check_contact(one, segments[i], "box query");
        check_contact(many[i], segments[i], "box query_many");
        const bool finite = segments[i].start.allFinite() && segments[i].end.allFinite();
        if (finite && !same(one, many[i])) hb::fuzz::fail("query_many differs from query on a finite segment");
        check_contact(scene.query(segments[i], law), segments[i], "scene query");
        check_contact(probe.query(segments[i], law), segments[i], "scene query with a state");
      }
    }
  } catch (const hb::Error& e) {
    hb::fuzz::check_rejection(e, path);
  }
  return 0;
}
