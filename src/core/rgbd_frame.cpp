#include "vocal/core/rgbd_frame.h"

#include <sstream>

#include "vocal/core/errors.h"

namespace vocal {

void RgbdFrame::validate(const std::string& what) const {
  if (color.empty() || depth.empty()) {
    throw InputError(what + ": " + (color.empty() ? "colour" : "depth") + " image is empty");
  }
  if (!color.sameSize(depth)) {
    std::ostringstream message;
    message << what << ": colour image is " << color.width() << "x" << color.height() << " but depth image is "
            << depth.width() << "x" << depth.height() << " (depth must be registered to colour)";
    throw InputError(message.str());
  }
}

}  // namespace vocal
