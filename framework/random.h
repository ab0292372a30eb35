#pragma once
// Deterministic random streams: xoshiro256** seeded through splitmix64, normal deviates by the polar
// Box-Muller method. Written out here (not std::normal_distribution) so that the same seed gives the same
// bytes with every standard library.
#include <cstdint>

namespace kincal {

class Rng {
 public:
  explicit Rng(uint64_t seed);
  uint64_t NextU64();
  double Uniform01();                       // [0, 1)
  double Uniform(double low, double high);  // [low, high)
  double Normal();                          // mean 0, standard deviation 1
  // An independent stream derived from this seed and a label, e.g. one per Monte Carlo trial.
  static uint64_t Derive(uint64_t seed, uint64_t label);

 private:
  uint64_t s_[4];
  bool have_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace kincal
