// Batched haptic box queries, several side by side in the lanes of SIMD vectors.
//
// query() is one long dependency chain (square roots and divisions from the probe to the
// sample addresses, then from the samples to t0) of about 1,100 instructions, longer than
// the core's reorder window: two queries in a row hardly overlap, even when their samples are
// in cache. Here lane q of every vector belongs to query q, so each instruction advances 4 or
// 8 queries and their chains run side by side. query_many() uses this path for raw tables
// without refinement (the common case for evaluations, error fields and several contact
// points per tick); codecs and refining boxes keep the one-query path.
//
// Every arithmetic step is the one query() performs, in the same order and association, on
// the same operands (IEEE single precision, no fused multiply-add: this file is built with
// -ffp-contract=off), so the answers are query()'s bit for bit at every level
// (tests/core/query_many_test.cpp checks each level the CPU has). A lane whose segment misses
// the box reads the table's first samples and is answered "no contact".
//
// The kernel (query_lanes_kernel.inc) is compiled once per level, each copy in its own
// namespace under `#pragma GCC target` (clang: `#pragma clang attribute` with the same target),
// and the best level the CPU has is picked at run time:
//   sse2    4 lanes, the x86-64 baseline;
//   avx     4 lanes, three-operand (VEX) forms: no register copies;
//   avx2    8 lanes (256-bit vectors);
//   avx512  8 lanes with AVX-512VL's 32 vector registers: fewer spills.
#include "box/haptic_box.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <immintrin.h>

namespace hb {
namespace {

// What the kernel needs of a box, in plain arrays, and the box's layout (box_layout.h) for
// the sample addresses.
struct LaneBox {
  float rt[3][3], center[3], half[3], grid_scale[3];
  float frames[6][9];  // per face: origin, step_i, step_j (world)
  int m, n;
  const BoxLayout* layout;
  const Sample* table;
  const HapticBox* box;  // answers the lanes the scalar query takes (steps 6a and 6b)
};

} // namespace
} // namespace hb

#define HB_LANES_INLINE __attribute__((always_inline)) inline

#define HB_LANES_WIDTH 4
namespace hb::lanes_sse2 {
#include "box/query_lanes_kernel.inc"
}
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx")
#endif
namespace hb::lanes_avx {
#include "box/query_lanes_kernel.inc"
}
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#undef HB_LANES_WIDTH

#define HB_LANES_WIDTH 8
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
namespace hb::lanes_avx2 {
#include "box/query_lanes_kernel.inc"
}
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,avx512f,avx512vl"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,avx512f,avx512vl")
#endif
namespace hb::lanes_avx512 {
#include "box/query_lanes_kernel.inc"
}
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#undef HB_LANES_WIDTH

namespace hb {
namespace {

std::atomic<int> lane_isa_cap{int(LaneIsa::avx512)};

LaneIsa best_lane_isa() noexcept {
  static const LaneIsa best = __builtin_cpu_supports("avx512vl") ? LaneIsa::avx512
                              : __builtin_cpu_supports("avx2")   ? LaneIsa::avx2
                              : __builtin_cpu_supports("avx")    ? LaneIsa::avx
                                                                 : LaneIsa::sse2;
  return best;
}

} // namespace

LaneIsa lane_isa() noexcept {
  return LaneIsa(std::min(int(best_lane_isa()), lane_isa_cap.load(std::memory_order_relaxed)));
}

const char* lane_isa_name(LaneIsa isa) noexcept {
  switch (isa) {
  case LaneIsa::avx512:
    return "avx512";
  case LaneIsa::avx2:
    return "avx2";
  case LaneIsa::avx:
    return "avx";
  default:
    return "sse2";
  }
}

void set_lane_isa_cap(LaneIsa cap) noexcept { lane_isa_cap.store(int(cap), std::memory_order_relaxed); }

void HapticBox::query_many_lanes(const Segment* segments, std::size_t count, const ForceLaw& law,
                                 Contact* out) const noexcept {
  LaneBox b;
  const BoxLayout::Local& local = layout_.local();
  for (int a = 0; a < 3; ++a) {
    for (int k = 0; k < 3; ++k) b.rt[a][k] = local.rt[a][k];
    b.center[a] = local.center[a];
    b.half[a] = local.half[a];
    b.grid_scale[a] = local.grid_scale[a];
  }
  for (int face = 0; face < 6; ++face)
    for (int a = 0; a < 3; ++a) {
      const BoxLayout::FaceFrame& frame = layout_.frame(face);
      b.frames[face][a] = frame.origin[a];
      b.frames[face][3 + a] = frame.step_i[a];
      b.frames[face][6 + a] = frame.step_j[a];
    }
  b.m = params_.m;
  b.n = params_.n;
  b.layout = &layout_;
  b.table = table_;
  b.box = this;
  switch (lane_isa()) {
  case LaneIsa::avx512:
    return lanes_avx512::run(b, segments, count, law, out);
  case LaneIsa::avx2:
    return lanes_avx2::run(b, segments, count, law, out);
  case LaneIsa::avx:
    return lanes_avx::run(b, segments, count, law, out);
  default:
    return lanes_sse2::run(b, segments, count, law, out);
  }
}

} // namespace hb
