#pragma once

#include <string>

#include "vocal/core/image.h"

namespace vocal {

// One colour image and the depth registered to it (same size, same camera), with its stamp.
struct RgbdFrame {
  double stamp = 0.0;
  ColorImage color;
  DepthImage depth;  // metres, 0 where there is no measurement

  // Throws InputError naming `what` when the images are empty or of different sizes.
  void validate(const std::string& what) const;
};

}  // namespace vocal
