#include "vocal/calibration/output/calibrated_urdf.h"

#include <fstream>
#include <iomanip>
#include <sstream>

#include "vocal/core/errors.h"

namespace vocal {

std::string withJointOffsets(const std::string& urdf, const std::map<std::string, double>& offsets, const std::string& what) {
  std::string out = urdf;
  for (const auto& [name, offset] : offsets) {
    // The joint's element: from <joint name="NAME" (either quote) to its </joint>.
    std::size_t begin = std::string::npos;
    for (const char quote : {'"', '\''}) {
      const std::size_t at = out.find(std::string("name=") + quote + name + quote);
      if (at == std::string::npos) continue;
      const std::size_t open = out.rfind("<joint", at);
      if (open != std::string::npos && out.find('>', open) > at) begin = open;
    }
    if (begin == std::string::npos) throw InputError(what + ": the URDF has no joint '" + name + "' to write its offset to");
    const std::size_t end = out.find("</joint>", begin);
    if (end == std::string::npos) throw InputError(what + ": joint '" + name + "' has no </joint>");
    // Its <calibration .../> removed, the new one added before </joint>.
    std::string element = out.substr(begin, end - begin);
    for (std::size_t c = element.find("<calibration"); c != std::string::npos; c = element.find("<calibration")) {
      const std::size_t close = element.find("/>", c);
      if (close == std::string::npos) throw InputError(what + ": joint '" + name + "' has a <calibration> that is not closed with />");
      std::size_t line_start = element.rfind('\n', c);
      line_start = line_start == std::string::npos || element.find_first_not_of(" \t", line_start + 1) != c ? c : line_start;
      element.erase(line_start, close + 2 - line_start);
    }
    std::ostringstream calibration;
    calibration << std::setprecision(9) << "  <calibration rising=\"" << offset << "\"/>\n  ";
    out = out.substr(0, begin) + element + calibration.str() + out.substr(end);
  }
  return out;
}

void writeCalibratedUrdf(const std::string& from, const std::string& to, const std::map<std::string, double>& offsets) {
  std::ifstream in(from);
  if (!in) throw InputError(from + ": cannot read the URDF");
  std::stringstream text;
  text << in.rdbuf();
  std::ofstream out(to);
  if (!out) throw InputError(to + ": cannot write the calibrated URDF");
  out << withJointOffsets(text.str(), offsets, from);
  if (!out.flush()) throw InputError(to + ": write error");
}

}  // namespace vocal
