#include "vocal/simulation/procedural_texture.h"

#include <algorithm>
#include <cmath>

namespace vocal {

namespace {
double latticeValue(std::int64_t ix, std::int64_t iy, std::uint32_t seed) {
  // Integer hash (splitmix-style mixing): no visible period over any practical extent.
  std::uint64_t h = static_cast<std::uint64_t>(ix) * 0x9E3779B97F4A7C15ULL ^
                    static_cast<std::uint64_t>(iy) * 0xC2B2AE3D27D4EB4FULL ^ (static_cast<std::uint64_t>(seed) << 32);
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBULL;
  h ^= h >> 31;
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

double quintic(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

double valueNoise(double a, double b, std::uint32_t seed) {
  const double fa = std::floor(a);
  const double fb = std::floor(b);
  const auto ia = static_cast<std::int64_t>(fa);
  const auto ib = static_cast<std::int64_t>(fb);
  const double sa = quintic(a - fa);
  const double sb = quintic(b - fb);
  const double v00 = latticeValue(ia, ib, seed);
  const double v10 = latticeValue(ia + 1, ib, seed);
  const double v01 = latticeValue(ia, ib + 1, seed);
  const double v11 = latticeValue(ia + 1, ib + 1, seed);
  return (v00 * (1 - sa) + v10 * sa) * (1 - sb) + (v01 * (1 - sa) + v11 * sa) * sb;
}
}  // namespace

double fractalNoise(double a, double b, std::uint32_t seed) {
  // Lattice frequencies in cells per metre and their weights (sum 1). The finest period (4 cm) stays
  // above 3 pixels at 3 m for a 320x240 Kinect image, so views sample it without aliasing.
  static const double kFrequency[] = {1.5, 4.0, 9.0, 25.0};
  static const double kWeight[] = {0.3, 0.25, 0.25, 0.2};
  double value = 0.0;
  for (int octave = 0; octave < 4; ++octave) {
    value += kWeight[octave] * valueNoise(a * kFrequency[octave], b * kFrequency[octave], seed + 7919u * octave);
  }
  // Averaging octaves concentrates values near 0.5; stretch back to real-world contrast.
  return std::min(1.0, std::max(0.0, 0.5 + 2.5 * (value - 0.5)));
}

}  // namespace vocal
