#pragma once
// Band-limited, non-repeating procedural texture (value-noise fBm) evaluated in a surface's own
// metric coordinates, so a surface point has the same colour from every viewpoint.

#include <cstdint>

namespace vocal {

// Fractal value noise in [0, 1] at (a, b) metres. Finest octave has a period of about 6 cm, coarse
// enough to stay unaliased at Kinect resolution up to several metres.
double fractalNoise(double a, double b, std::uint32_t seed);

}  // namespace vocal
