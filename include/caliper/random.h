// Seeded random numbers that are the same on every machine and library version
// (std::normal_distribution is implementation-defined): splitmix64 + Box–Muller.
// Passed in explicitly wherever randomness is used; there is no global generator.
#pragma once
#include <cmath>
#include <cstdint>

namespace caliper {

class NormalGenerator {
 public:
  explicit NormalGenerator(std::uint64_t seed) : state_(seed ? seed : 1) {}
  double uniform() {  // in (0, 1)
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 0.5) / 9007199254740992.0;
  }
  double normal() {  // standard normal
    if (has_spare_) { has_spare_ = false; return spare_; }
    const double r = std::sqrt(-2.0 * std::log(uniform())), t = 2.0 * M_PI * uniform();
    spare_ = r * std::sin(t);
    has_spare_ = true;
    return r * std::cos(t);
  }

 private:
  std::uint64_t state_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace caliper
