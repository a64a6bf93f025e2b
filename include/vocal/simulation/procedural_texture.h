#pragma once
// Band-limited, non-repeating procedural texture (value-noise fBm) evaluated in a surface's own
// metric coordinates, so a surface point has the same colour from every viewpoint.

#include <cstdint>

namespace vocal {

// Fractal value noise in [0, 1] at (a, b) metres, contrast-stretched: strong gradients at every
// scale from 4 cm to 70 cm, like printed or natural surface texture.
double fractalNoise(double a, double b, std::uint32_t seed);

}  // namespace vocal
