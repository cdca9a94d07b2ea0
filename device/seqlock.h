#pragma once
// Single-writer, many-reader seqlock: the servo thread publishes, the GUI reads at display
// rate; neither side blocks or allocates. The payload is stored as relaxed atomic words so
// that a torn read is a retry, never a data race.
#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace hb {

template <class T>
class Seqlock {
  static_assert(std::is_trivially_copyable_v<T>, "Seqlock payload must be trivially copyable");
  static constexpr std::size_t words = (sizeof(T) + 7) / 8;

public:
  Seqlock() noexcept {
    for (auto& w : data_) w.store(0, std::memory_order_relaxed);
  }
  explicit Seqlock(const T& initial) noexcept : Seqlock() { store(initial); }

  /// Writer side (one thread only).
  void store(const T& value) noexcept {
    std::uint64_t buf[words] = {};
    std::memcpy(buf, &value, sizeof(T));
    const std::uint64_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < words; ++i) data_[i].store(buf[i], std::memory_order_relaxed);
    seq_.store(s + 2, std::memory_order_release);
  }

  /// Reader side (any thread): retries while a write is in progress.
  T load() const noexcept {
    std::uint64_t buf[words];
    for (;;) {
      const std::uint64_t s0 = seq_.load(std::memory_order_acquire);
      if (s0 & 1) continue;
      for (std::size_t i = 0; i < words; ++i) buf[i] = data_[i].load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) break;
    }
    T out;
    std::memcpy(&out, buf, sizeof(T));
    return out;
  }

  /// Number of completed stores.
  std::uint64_t version() const noexcept { return seq_.load(std::memory_order_acquire) / 2; }

private:
  std::atomic<std::uint64_t> seq_{0};
  std::atomic<std::uint64_t> data_[words];
};

} // namespace hb
