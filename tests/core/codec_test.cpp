// Table codecs on real (baked) tables: error bounds, random access, hit/miss, corruption,
// file round trip. Small boxes from generated meshes keep the suite fast.
#include "codec/sample_table.h"
#include "errors.h"
#include "geometry/octahedral.h"
#include "scene/bake.h"
#include "store/box_file.h"
#include "mesh/mesh_io.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <fstream>
#include <random>
#include <unistd.h>

namespace hb {
namespace {

namespace fs = std::filesystem;

// Bumpy sphere and torus boxes, baked once: n = 12 gives partial 8 x 8 blocks and a padded
// Haar tile (N = 16); the torus has misses and silhouettes in most tiles.
struct Boxes {
  HapticBox bumpy, torus;
};
const Boxes& boxes() {
  static const Boxes b = [] {
    BakeOptions options;
    options.params = {6, 12};
    BumpySphereOptions bumpy;
    bumpy.subdivisions = 4;
    const TriangleMesh a = make_bumpy_sphere(bumpy);
    const TriangleMesh t = make_torus(1.f, 0.35f, 48, 24);
    return Boxes{bake_box(a, {}, options), bake_box(t, {}, options)};
  }();
  return b;
}

CodecOptions options(CodecId codec, float max_error) {
  CodecOptions o;
  o.codec = codec;
  o.max_error = max_error;
  return o;
}

// Checks every sample of `c` against the raw `box` directly (not through CodecStats).
void expect_within_bound(const HapticBox& box, const HapticBox& c, float bound, int normal_bits) {
  const BoxParams& p = box.params();
  const std::size_t per_tile = std::size_t(p.n) * std::size_t(p.n);
  const double limit = double(bound) * double(box.obb().diagonal());
  const double n_limit = 1.0 / double((1 << normal_bits) - 1) + 1e-6;
  std::vector<DecodedSample> dec(per_tile);
  std::size_t hits = 0;
  for (std::size_t tile = 0; tile < p.tile_count(); ++tile) {
    c.samples().decode_tile(tile, dec.data());
    for (std::size_t i = 0; i < per_tile; ++i) {
      const Sample& s = box.table()[tile * per_tile + i];
      ASSERT_EQ(s.t >= 0.f, dec[i].t >= 0.f) << "hit/miss changed at tile " << tile << " sample " << i;
      if (s.t < 0.f) continue;
      ++hits;
      ASSERT_LE(std::fabs(double(dec[i].t) - double(s.t)), limit) << "tile " << tile << " sample " << i;
      ASSERT_LE(std::fabs(dec[i].u - float(std::int16_t(s.normal & 0xffffu)) / 32767.f), n_limit);
      ASSERT_LE(std::fabs(dec[i].v - float(std::int16_t(s.normal >> 16)) / 32767.f), n_limit);
    }
  }
  EXPECT_GT(hits, 0u);
  EXPECT_LE(c.codec_stats().t_error_max, bound);
  EXPECT_EQ(c.codec_stats().hit_miss_flips, 0u);
}

void expect_random_access_equals_full_decode(const HapticBox& c) {
  const BoxParams& p = c.params();
  std::vector<DecodedSample> dec(std::size_t(p.n) * std::size_t(p.n));
  for (std::size_t tile = 0; tile < p.tile_count(); tile += 7) {
    c.samples().decode_tile(tile, dec.data());
    for (int a = 0; a < p.n; ++a)
      for (int b = 0; b < p.n; ++b) {
        const DecodedSample one = c.samples().decode(tile, a, b);
        const DecodedSample& all = dec[std::size_t(a * p.n + b)];
        ASSERT_EQ(one.t, all.t) << "tile " << tile << " (" << a << ", " << b << ")";
        ASSERT_EQ(one.u, all.u);
        ASSERT_EQ(one.v, all.v);
      }
  }
}

TEST(BlockCodecTest, ErrorBoundIsHonouredOnRealTables) {
  for (float bound : {1e-4f, 1e-3f, 1e-2f}) {
    expect_within_bound(boxes().bumpy, boxes().bumpy.compressed(options(CodecId::block, bound)), bound, CodecOptions{}.normal_bits);
    expect_within_bound(boxes().torus, boxes().torus.compressed(options(CodecId::block, bound)), bound, CodecOptions{}.normal_bits);
  }
}

TEST(HaarCodecTest, ErrorBoundIsHonouredOnRealTables) {
  for (float bound : {1e-4f, 1e-3f, 1e-2f}) {
    expect_within_bound(boxes().bumpy, boxes().bumpy.compressed(options(CodecId::haar, bound)), bound, CodecOptions{}.normal_bits);
    expect_within_bound(boxes().torus, boxes().torus.compressed(options(CodecId::haar, bound)), bound, CodecOptions{}.normal_bits);
  }
}

TEST(BlockCodecTest, CoarseNormalsStayWithinTheirBound) {
  CodecOptions o = options(CodecId::block, 1e-3f);
  o.normal_bits = 7;
  expect_within_bound(boxes().torus, boxes().torus.compressed(o), 1e-3f, 7);
}

TEST(BlockCodecTest, RandomAccessEqualsFullDecode) {
  expect_random_access_equals_full_decode(boxes().torus.compressed(options(CodecId::block, 1e-3f)));
  expect_random_access_equals_full_decode(boxes().bumpy.compressed(options(CodecId::block, 1e-4f)));
}

TEST(HaarCodecTest, RandomAccessEqualsFullDecode) {
  expect_random_access_equals_full_decode(boxes().torus.compressed(options(CodecId::haar, 1e-3f)));
  expect_random_access_equals_full_decode(boxes().bumpy.compressed(options(CodecId::haar, 1e-4f)));
}

// fetch_quad() against four fetch() calls, bit for bit: every quad (all a0, b0 up to the
// tile's last row and column) of every sub-block face of some positions, then random quads
// of random tiles; with the portable bitmap ranks, then with popcnt where the CPU has it.
// A miss is compared as {kMissT, 0, 0} (decode()'s form; fetch() leaves a miss's values
// unspecified). The block codec's quads are checked the same way (one view, no popcnt switch).
template <class View>
void expect_quad_equals_fetch(const View& view, const BoxParams& p, std::size_t all_quad_positions,
                              std::size_t random_quads);
void expect_quad_equals_fetch(const HapticBox& c, std::size_t all_quad_positions, std::size_t random_quads) {
  if (c.samples().codec() == CodecId::block) {
    expect_quad_equals_fetch(c.samples().block(), c.params(), all_quad_positions, random_quads);
    return;
  }
  ASSERT_EQ(c.samples().codec(), CodecId::haar);
  for (bool hardware : {false, true}) {
    SCOPED_TRACE(hardware ? "popcnt" : "portable popcount");
    HaarTable view = c.samples().haar();
    view.use_hardware_popcount(hardware);
    expect_quad_equals_fetch(view, c.params(), all_quad_positions, random_quads);
  }
}
template <class View>
void expect_quad_equals_fetch(const View& view, const BoxParams& p, std::size_t all_quad_positions,
                              std::size_t random_quads) {
  const auto bits = [](float x) {
    std::uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
  };
  std::size_t hits = 0, quads = 0;
  const auto check = [&](std::size_t tile, int a0, int b0) {
    float t[4], u[4], v[4];
    const unsigned mask = view.fetch_quad(tile, a0, b0, t, u, v);
    const int qa[4] = {a0, a0 + 1, a0 + 1, a0}, qb[4] = {b0, b0, b0 + 1, b0 + 1};
    for (int k = 0; k < 4; ++k) {
      float t1 = kMissT, u1 = 0.f, v1 = 0.f;
      const bool hit = view.fetch(tile, qa[k], qb[k], t1, u1, v1);
      if (!hit) t1 = kMissT, u1 = v1 = 0.f;
      ASSERT_EQ(hit, bool((mask >> k) & 1u)) << "tile " << tile << " (" << qa[k] << ", " << qb[k] << ")";
      ASSERT_EQ(bits(t[k]), bits(t1)) << "tile " << tile << " (" << qa[k] << ", " << qb[k] << ")";
      ASSERT_EQ(bits(u[k]), bits(u1)) << "tile " << tile << " (" << qa[k] << ", " << qb[k] << ")";
      ASSERT_EQ(bits(v[k]), bits(v1)) << "tile " << tile << " (" << qa[k] << ", " << qb[k] << ")";
      hits += hit;
    }
    ++quads;
  };
  const std::size_t positions = p.position_count();
  for (std::size_t position = 0; position < positions; position += 1 + positions / all_quad_positions)
    for (std::size_t sf = 0; sf < 12; ++sf)
      for (int a0 = 0; a0 + 1 < p.n; ++a0)
        for (int b0 = 0; b0 + 1 < p.n; ++b0) {
          check(position * 12u + sf, a0, b0);
          if (::testing::Test::HasFatalFailure()) return;
        }
  std::mt19937 rng(5);
  for (std::size_t i = 0; i < random_quads; ++i) {
    check(rng() % p.tile_count(), int(rng() % unsigned(p.n - 1)), int(rng() % unsigned(p.n - 1)));
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(hits, 0u);
  EXPECT_LT(hits, 4 * quads);  // mixed tiles were met
}

TEST(HaarCodecTest, QuadFetchEqualsPerSampleFetch) {
  expect_quad_equals_fetch(boxes().torus.compressed(options(CodecId::haar, 1e-3f)), 40, 20000);
  expect_quad_equals_fetch(boxes().bumpy.compressed(options(CodecId::haar, 1e-4f)), 40, 20000);
}

// Tile sizes: N = 2, 8 (padded), 16 (unpadded), 64 (padded, the largest on the stack path)
// and 128 (n > 64: the sample-by-sample path).
TEST(HaarCodecTest, QuadFetchEqualsPerSampleFetchAtEveryTileSize) {
  const TriangleMesh torus = make_torus(1.f, 0.35f, 48, 24);
  for (const BoxParams params : {BoxParams{4, 2}, BoxParams{4, 5}, BoxParams{4, 16}, BoxParams{2, 33}, BoxParams{2, 65}}) {
    SCOPED_TRACE("n = " + std::to_string(params.n));
    BakeOptions o;
    o.params = params;
    expect_quad_equals_fetch(bake_box(torus, {}, o).compressed(options(CodecId::haar, 1e-3f)), params.n > 16 ? 3 : 40,
                             5000);
  }
}

// The real armadillo (datasets/fetch.sh), one raw box, m = 4, n = 16 (the query's tile
// size), baked once for the codecs' quad tests; nullptr when the datasets are absent.
const HapticBox* armadillo_box() {
  static const std::unique_ptr<HapticBox> box = [] {
    const fs::path mesh = fs::path(HB_DATASETS_DIR) / "meshes" / "armadillo.off";
    if (!fs::exists(mesh)) return std::unique_ptr<HapticBox>();
    BakeOptions o;
    o.params = {4, 16};
    return std::make_unique<HapticBox>(bake_box(read_mesh(mesh.string()), {}, o));
  }();
  return box.get();
}

TEST(HaarCodecTest, QuadFetchEqualsPerSampleFetchOnArmadillo) {
  const HapticBox* box = armadillo_box();
  if (!box) GTEST_SKIP() << "datasets/data is absent: run datasets/fetch.sh";
  expect_quad_equals_fetch(box->compressed(options(CodecId::haar, 1e-3f)), 40, 50000);
}

TEST(BlockCodecTest, QuadFetchEqualsPerSampleFetch) {
  // n = 12: the last row and column of 8 x 8 blocks are partial; quads across blocks too.
  expect_quad_equals_fetch(boxes().torus.compressed(options(CodecId::block, 1e-3f)), 40, 20000);
  expect_quad_equals_fetch(boxes().bumpy.compressed(options(CodecId::block, 1e-4f)), 40, 20000);
}

// Synthetic tables, every quad of every tile: per tile one pattern (all miss, all hit and
// smooth: mode 1 blocks with plane predictors, scattered misses and a silhouette: mode 2
// blocks, noise: wide residuals), at tile sizes with no, partial and one-sample-wide blocks.
TEST(BlockCodecTest, QuadFetchEqualsPerSampleFetchOnSyntheticTables) {
  for (int n : {2, 5, 8, 9, 12, 16, 17, 24}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const BoxParams p{2, n};
    std::vector<Sample> raw(p.sample_count());
    std::mt19937 rng(std::uint32_t(7 + n));
    std::uniform_real_distribution<float> unit(0.f, 1.f);
    const auto oct = [](float u, float v) {
      return std::uint32_t(std::uint16_t(std::int16_t(std::lround(u * 32767.f)))) |
             (std::uint32_t(std::uint16_t(std::int16_t(std::lround(v * 32767.f)))) << 16);
    };
    const std::size_t per_tile = std::size_t(n) * std::size_t(n);
    for (std::size_t tile = 0; tile < p.tile_count(); ++tile) {
      const unsigned pattern = unsigned(tile % 5);
      const float t0 = 5.f * unit(rng), ga = unit(rng) - 0.5f, gb = unit(rng) - 0.5f;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          Sample& s = raw[tile * per_tile + std::size_t(a * n + b)];
          const float fa = float(a) / float(n), fb = float(b) / float(n);
          bool hit = true;
          float t = t0 + ga * float(a) + gb * float(b), u = 0.8f * fa - 0.4f, v = 0.5f - 0.9f * fb;
          if (pattern == 0) hit = false;
          if (pattern == 2) hit = unit(rng) < 0.7f;
          if (pattern == 3) hit = a + 2 * b < n + 3;
          if (pattern == 4) t = 8.f * unit(rng), u = 2.f * unit(rng) - 1.f, v = 2.f * unit(rng) - 1.f;
          s = hit ? Sample{std::max(t, 0.f), oct(u, v)} : Sample{kMissT, 0u};
        }
    }
    const std::vector<std::uint8_t> payload = encode_block_table(raw.data(), p, 2e-3f, 1.f / 1023.f);
    const BlockTable view(payload.data(), payload.size(), p);
    expect_quad_equals_fetch(view, p, p.position_count(), 20000);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

TEST(BlockCodecTest, QuadFetchEqualsPerSampleFetchOnArmadillo) {
  const HapticBox* box = armadillo_box();
  if (!box) GTEST_SKIP() << "datasets/data is absent: run datasets/fetch.sh";
  for (float bound : {1e-4f, 1e-3f}) expect_quad_equals_fetch(box->compressed(options(CodecId::block, bound)), 40, 50000);
}

TEST(CodecTest, HitMissIsPreservedExactlyEvenAtLooseBounds) {
  for (CodecId codec : {CodecId::block, CodecId::haar}) {
    const HapticBox c = boxes().torus.compressed(options(codec, 0.1f));
    EXPECT_EQ(c.codec_stats().hit_miss_flips, 0u) << codec_name(codec);
    const BoxParams& p = c.params();
    for (std::size_t tile = 0; tile < p.tile_count(); tile += 3)
      for (int a = 0; a < p.n; ++a)
        for (int b = 0; b < p.n; ++b) {
          const Sample& s = boxes().torus.table()[(tile * std::size_t(p.n) + std::size_t(a)) * std::size_t(p.n) + std::size_t(b)];
          ASSERT_EQ(s.t >= 0.f, c.samples().decode(tile, a, b).t >= 0.f);
        }
  }
}

TEST(CodecTest, CompressedQueryAgreesWithRawQuery) {
  const HapticBox& raw = boxes().bumpy;
  const HapticBox c = raw.compressed(options(CodecId::block, 2e-4f));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  int agree = 0, total = 0;
  double depth_err = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 tip = dir * (0.95f + 0.1f * u(rng));
    const Segment s{tip + dir * 0.5f, tip};
    const Contact a = raw.query(s, {}), b = c.query(s, {});
    ++total;
    agree += a.contact == b.contact;
    if (a.contact && b.contact) depth_err = std::max(depth_err, double(std::fabs(a.depth - b.depth)));
  }
  EXPECT_GE(double(agree) / total, 0.99);
  // The bound, times a little for the tangent-plane correction through the normals.
  EXPECT_LE(depth_err, 4.0 * 2e-4 * raw.obb().diagonal());
}

TEST(CodecTest, RatioTargetIsReached) {
  CodecOptions o;
  o.codec = CodecId::block;
  o.ratio = 6.f;
  const HapticBox c = boxes().bumpy.compressed(o);
  EXPECT_GE(c.codec_stats().ratio(), 6.0);
  EXPECT_LE(c.codec_stats().t_error_max, c.codec_stats().max_error_bound);
}

TEST(CodecTest, OutOfRangeOptionsAreRejected) {
  EXPECT_THROW(boxes().bumpy.compressed(options(CodecId::block, 0.5f)), InvalidInput);
  EXPECT_THROW(boxes().bumpy.compressed(options(CodecId::none, 1e-3f)), InvalidInput);
  CodecOptions o = options(CodecId::haar, 1e-3f);
  o.normal_bits = 20;
  EXPECT_THROW(boxes().bumpy.compressed(o), InvalidInput);
  EXPECT_THROW(parse_codec("zip"), InvalidInput);
  const HapticBox c = boxes().bumpy.compressed(options(CodecId::block, 1e-3f));
  EXPECT_THROW(c.compressed(options(CodecId::block, 1e-3f)), InvalidInput);
}

TEST(CodecTest, CorruptPayloadHeaderIsRejected) {
  for (CodecId codec : {CodecId::block, CodecId::haar}) {
    CompressedTable t = compress_table(boxes().bumpy.table(), boxes().bumpy.params(), boxes().bumpy.obb().diagonal(),
                                       options(codec, 1e-3f));
    std::vector<std::uint8_t> bad = t.payload;
    bad[0] ^= 0xff;  // magic
    EXPECT_THROW(SampleTable(codec, bad.data(), bad.size(), boxes().bumpy.params()), InvalidInput);
    bad = t.payload;
    bad.resize(bad.size() / 2);  // truncated
    try {
      SampleTable(codec, bad.data(), bad.size(), boxes().bumpy.params());
      FAIL() << "truncated payload accepted";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("compressed payload"), std::string::npos) << e.what();
    }
    EXPECT_THROW(SampleTable(codec, t.payload.data(), t.payload.size(), BoxParams{6, 10}), InvalidInput);
  }
}

// Garbage in the index and the data, header intact: the view is accepted (lazy loading
// validates the header only), the garbage is read (some samples change), and every sample and
// quad it gives is still a well-formed answer: a miss {kMissT, 0, 0}, or a hit with a finite
// t >= 0 and normal components in [-1, 1], each quad's hit mask matching its t's. That every
// read also stays inside the payload is checked where it can be: this test runs in the
// AddressSanitizer suites of ./test.sh's hostile-input stage (build-asan/), where an
// out-of-bounds read fails it.
TEST(CodecTest, CorruptRecordsDecodeToWellFormedSamples) {
  const auto well_formed = [](float t, float u, float v) {
    if (t == kMissT) return u == 0.f && v == 0.f;
    return std::isfinite(t) && t >= 0.f && u >= -1.f && u <= 1.f && v >= -1.f && v <= 1.f;
  };
  for (CodecId codec : {CodecId::block, CodecId::haar}) {
    SCOPED_TRACE(codec == CodecId::block ? "block" : "haar");
    CompressedTable t = compress_table(boxes().torus.table(), boxes().torus.params(), boxes().torus.obb().diagonal(),
                                       options(codec, 1e-3f));
    const std::vector<std::uint8_t> intact_payload = t.payload;
    PayloadHeader h;
    std::memcpy(&h, t.payload.data(), sizeof(h));
    std::mt19937 rng(11);
    for (std::size_t i = h.index_offset; i < h.data_offset + h.data_bytes; i += 1 + rng() % 64)
      t.payload[i] = std::uint8_t(rng());
    const BoxParams& p = boxes().torus.params();
    const SampleTable intact(codec, intact_payload.data(), intact_payload.size(), p);
    const SampleTable view(codec, t.payload.data(), t.payload.size(), p);
    std::size_t changed = 0, malformed = 0;
    for (std::size_t tile = 0; tile < p.tile_count(); ++tile)
      for (int a = 0; a < p.n; ++a)
        for (int b = 0; b < p.n; ++b) {
          const DecodedSample s = view.decode(tile, a, b), o = intact.decode(tile, a, b);
          if (!well_formed(s.t, s.u, s.v)) ++malformed;
          if (s.t != o.t || s.u != o.u || s.v != o.v) ++changed;
        }
    EXPECT_EQ(malformed, 0u) << "decode() gave a sample that is neither a miss nor a valid hit";
    EXPECT_GT(changed, 0u) << "the corruption was never read: the test exercises nothing";
    const auto check_quad = [&](unsigned mask, const float* qt, const float* qu, const float* qv) {
      for (int k = 0; k < 4; ++k) {
        const bool hit = (mask >> k) & 1u;
        if (!well_formed(qt[k], qu[k], qv[k]) || hit != (qt[k] >= 0.f)) ++malformed;
      }
    };
    if (codec == CodecId::block)
      for (std::size_t tile = 0; tile < p.tile_count(); ++tile)
        for (int a0 = 0; a0 + 1 < p.n; ++a0)
          for (int b0 = 0; b0 + 1 < p.n; ++b0) {
            float qt[4], qu[4], qv[4];
            check_quad(view.block().fetch_quad(tile, a0, b0, qt, qu, qv), qt, qu, qv);
          }
    for (bool hardware : {false, true}) {
      if (codec != CodecId::haar) break;
      HaarTable haar = view.haar();
      haar.use_hardware_popcount(hardware);
      for (std::size_t tile = 0; tile < p.tile_count(); ++tile)
        for (int a0 = 0; a0 + 1 < p.n; a0 += 3)
          for (int b0 = 0; b0 + 1 < p.n; ++b0) {
            float qt[4], qu[4], qv[4];
            check_quad(haar.fetch_quad(tile, a0, b0, qt, qu, qv), qt, qu, qv);
          }
    }
    EXPECT_EQ(malformed, 0u) << "fetch_quad() gave a sample that is neither a miss nor a valid hit";
  }
}

// A block record whose header would run past the data (the padding after the data covers
// only records with their header inside it) reads as a miss, however its bytes look.
TEST(CodecTest, BlockRecordTooCloseToTheEndOfTheDataReadsAsAMiss) {
  CompressedTable t = compress_table(boxes().torus.table(), boxes().torus.params(), boxes().torus.obb().diagonal(),
                                     options(CodecId::block, 1e-3f));
  PayloadHeader h;
  std::memcpy(&h, t.payload.data(), sizeof(h));
  const BoxParams& p = boxes().torus.params();
  // The first tile with a hit at (0, 0): its block 0 is tile * nb * nb.
  const SampleTable intact(CodecId::block, t.payload.data(), t.payload.size(), p);
  std::size_t tile = 0;
  while (tile < p.tile_count() && intact.decode(tile, 0, 0).t < 0.f) ++tile;
  ASSERT_LT(tile, p.tile_count());
  const std::size_t nb = std::size_t((p.n + BlockTable::kBlock - 1) / BlockTable::kBlock);
  const std::uint32_t late = std::uint32_t(h.data_bytes - BlockTable::kHeaderBytes + 1);
  std::memcpy(t.payload.data() + h.index_offset + 4 * tile * nb * nb, &late, 4);
  // A mixed-mode header with the widest residuals, a positive t base and a full hit mask (in
  // the padding) at that offset: read as a record, sample (0, 0) would be a hit.
  std::uint8_t* rec = t.payload.data() + h.data_offset + late;
  rec[0] = 2, rec[1] = 31, rec[2] = 0xff;
  const std::int32_t t_base = 1 << 20;
  std::memcpy(rec + 4, &t_base, 4);
  std::memset(rec + BlockTable::kHeaderBytes, 0xff, 8);
  const SampleTable view(CodecId::block, t.payload.data(), t.payload.size(), p);
  EXPECT_LT(view.decode(tile, 0, 0).t, 0.f);
  float qt[4], qu[4], qv[4];
  EXPECT_EQ(view.block().fetch_quad(tile, 0, 0, qt, qu, qv) & 1u, 0u);
  std::vector<DecodedSample> all(std::size_t(p.n) * std::size_t(p.n));
  view.decode_tile(tile, all.data());
  EXPECT_LT(all[0].t, 0.f);
}

class CodecFileTest : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hb_codec_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string save(const BoxScene& scene, const std::string& name) {
    const std::string p = (dir_ / name).string();
    save_box_file(scene, p);
    return p;
  }
  std::vector<char> read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  std::string write(const std::string& name, const std::vector<char>& data) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary).write(data.data(), std::streamsize(data.size()));
    return p;
  }
  fs::path dir_;
};

TEST_F(CodecFileTest, RoundTripGivesIdenticalAnswersAndStats) {
  for (CodecId codec : {CodecId::block, CodecId::haar}) {
    const BoxScene scene(SceneParts({boxes().torus.compressed(options(codec, 5e-4f)), boxes().bumpy}, {"x.off", 1u, 10u, 3.f}));
    const BoxScene loaded = load_box_file(save(scene, std::string("rt_") + codec_name(codec) + ".hbox"), LoadOptions{true});
    ASSERT_EQ(loaded.parts().boxes.size(), 2u);
    EXPECT_EQ(loaded.parts().boxes[0].codec(), codec);
    EXPECT_EQ(loaded.parts().boxes[1].codec(), CodecId::none);
    EXPECT_EQ(loaded.parts().boxes[0].table_bytes(), scene.parts().boxes[0].table_bytes());
    EXPECT_EQ(loaded.parts().boxes[0].codec_stats().t_error_max, scene.parts().boxes[0].codec_stats().t_error_max);
    EXPECT_EQ(loaded.parts().boxes[0].codec_stats().max_error_bound, 5e-4f);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-2.f, 2.f);
    for (int i = 0; i < 500; ++i) {
      const Segment s{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)) * 0.3f};
      const Contact a = scene.query(s, {}), b = loaded.query(s, {});
      ASSERT_EQ(a.contact, b.contact);
      EXPECT_EQ(a.depth, b.depth);
      EXPECT_EQ(a.force, b.force);
    }
  }
}

TEST_F(CodecFileTest, CorruptCompressedPayloadIsRejected) {
  const BoxScene scene(SceneParts({boxes().torus.compressed(options(CodecId::block, 1e-3f))}, {"x.off", 1u, 10u, 3.f}));
  const std::string path = save(scene, "good.hbox");
  auto data = read(path);
  // A flipped byte deep inside the payload: found by the checksum when verifying.
  auto bad = data;
  bad[bad.size() - 2000] ^= 0x5a;
  const std::string p1 = write("corrupt_payload.hbox", bad);
  try {
    load_box_file(p1, LoadOptions{true});
    FAIL() << "corrupt payload accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(p1), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
  // The payload's own header is checked even on a lazy open.
  const std::size_t payload_at = (data.size() - scene.parts().boxes[0].table_bytes()) / 64 * 64;
  ASSERT_EQ(std::memcmp(data.data() + payload_at, "HBTC", 4), 0);
  bad = data;
  bad[payload_at + 8] ^= 0x01;  // m
  const std::string p2 = write("corrupt_payload_header.hbox", bad);
  try {
    load_box_file(p2);
    FAIL() << "corrupt payload header accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(p2), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("compressed payload"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace hb
