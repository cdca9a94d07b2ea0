#pragma once
// Starting a cache line's load ahead of its use, one that the compiler keeps.
//
// GCC 12 (Debian's) deletes a __builtin_prefetch whose address is computed from a float
// converted to an integer (a lattice or cell index from a barycentric coordinate or a
// position): the builtin has no side effect it must keep, and the conversion may trap, so the
// whole computation goes (docs/speed.md, "Prefetches the compiler dropped"). An asm statement
// is kept as written. A prefetch never faults: `p` may point anywhere.

namespace hb {

inline void prefetch(const void* p) noexcept {
#if defined(__x86_64__) || defined(__i386__)
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

}  // namespace hb
