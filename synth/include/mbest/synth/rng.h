// Rng: the generator's only source of randomness. Portable (no std:: distributions, whose
// output differs between standard libraries), so a (seed, index) pair gives the same scene
// on every machine and whatever the job count.
#pragma once

#include <cmath>
#include <cstdint>

namespace mbest::synth {

// The per-scene seed: a hash of the dataset seed and the scene index only.
std::uint64_t scene_seed(std::uint64_t dataset_seed, std::uint64_t index);

// xoshiro256** seeded through splitmix64.
class Rng {
 public:
  explicit Rng(std::uint64_t seed);

  std::uint64_t next();
  double uniform();                          // [0, 1)
  double uniform(double lo, double hi);      // [lo, hi)
  int uniform_int(int lo, int hi);           // [lo, hi], both included
  double normal(double mean = 0, double sd = 1);
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t s_[4];
};

}  // namespace mbest::synth
