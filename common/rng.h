#pragma once
// Counter-based random numbers for reproducible simulation.
//
// Every random draw is a pure function of (seed, stream, counter): streams are derived from a
// stable name (e.g. "tls/noise") and per-item indices (scan id, ray index), never from thread
// or call order, so results are bit-identical with 1 or N threads. The distributions are our own
// (std:: distributions are not specified bit-for-bit across standard libraries).

#include <cmath>
#include <cstdint>
#include <string_view>

namespace mopad {

/// SplitMix64 finaliser: a strong 64-bit mixing function (Steele, Lea & Flood 2014).
constexpr std::uint64_t Mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// FNV-1a hash of a stream name: stable across runs, platforms and compilers.
constexpr std::uint64_t HashName(std::string_view name) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (char c : name) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001B3ull;
  return h;
}

/// Derives a child stream key from a parent key and an index (or a name hash).
constexpr std::uint64_t DeriveKey(std::uint64_t parent, std::uint64_t index) {
  return Mix64(parent ^ Mix64(index + 0x632BE59BD9B4E019ull));
}

/// A small generator over one key: draw i is Mix64(key, i). Cheap to construct per item
/// (e.g. one per ray), so noise never depends on which thread handles the item.
class CounterRng {
 public:
  explicit CounterRng(std::uint64_t key) : key_(key) {}
  CounterRng(std::uint64_t seed, std::string_view stream, std::uint64_t index = 0)
      : key_(DeriveKey(DeriveKey(Mix64(seed), HashName(stream)), index)) {}

  std::uint64_t NextU64() { return Mix64(key_ ^ Mix64(counter_++)); }
  /// Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  /// Integer in [0, n) (n > 0); Lemire's multiply-shift, negligible bias for n << 2^64.
  std::uint64_t Below(std::uint64_t n) {
    return static_cast<std::uint64_t>((static_cast<unsigned __int128>(NextU64()) * n) >> 64);
  }
  /// Standard normal by Box-Muller (two uniforms per draw; no cached state, so draws stay
  /// a pure function of the counter).
  double Normal() {
    const double u1 = 1.0 - Uniform();  // (0, 1]
    const double u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  double Normal(double mean, double sigma) { return mean + sigma * Normal(); }
  bool Bernoulli(double p) { return Uniform() < p; }

 private:
  std::uint64_t key_;
  std::uint64_t counter_ = 0;
};

}  // namespace mopad
