#include "vocal/calibration/output/calibrated_urdf.h"

#include <fstream>
#include <iomanip>
#include <sstream>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
// Where joint `name`'s element is in `urdf`: from <joint name="NAME" (either quote) to its </joint>.
std::pair<std::size_t, std::size_t> jointElement(const std::string& urdf, const std::string& name, const std::string& what, const char* writing) {
  std::size_t begin = std::string::npos;
  for (const char quote : {'"', '\''}) {
    const std::size_t at = urdf.find(std::string("name=") + quote + name + quote);
    if (at == std::string::npos) continue;
    const std::size_t open = urdf.rfind("<joint", at);
    if (open != std::string::npos && urdf.find('>', open) > at) begin = open;
  }
  if (begin == std::string::npos) throw InputError(what + ": the URDF has no joint '" + name + "' to write its " + writing + " to");
  const std::size_t end = urdf.find("</joint>", begin);
  if (end == std::string::npos) throw InputError(what + ": joint '" + name + "' has no </joint>");
  return {begin, end};
}

// `urdf` with joint `name`'s <TAG .../> elements removed and `line` added before its </joint>.
std::string withJointElement(const std::string& urdf, const std::string& name, const std::string& tag, const std::string& line,
                             const std::string& what, const char* writing) {
  const auto [begin, end] = jointElement(urdf, name, what, writing);
  std::string element = urdf.substr(begin, end - begin);
  for (std::size_t c = element.find("<" + tag); c != std::string::npos; c = element.find("<" + tag)) {
    const std::size_t close = element.find("/>", c);
    if (close == std::string::npos) throw InputError(what + ": joint '" + name + "' has a <" + tag + "> that is not closed with />");
    std::size_t line_start = element.rfind('\n', c);
    line_start = line_start == std::string::npos || element.find_first_not_of(" \t", line_start + 1) != c ? c : line_start;
    element.erase(line_start, close + 2 - line_start);
  }
  return urdf.substr(0, begin) + element + "  " + line + "\n  " + urdf.substr(end);
}
}  // namespace

std::string withJointOffsets(const std::string& urdf, const std::map<std::string, double>& offsets, const std::string& what) {
  std::string out = urdf;
  for (const auto& [name, offset] : offsets) {
    std::ostringstream calibration;
    calibration << std::setprecision(9) << "<calibration rising=\"" << offset << "\"/>";
    out = withJointElement(out, name, "calibration", calibration.str(), what, "offset");
  }
  return out;
}

std::string withJointOrigins(const std::string& urdf, const std::map<std::string, Eigen::Isometry3d>& origins, const std::string& what) {
  std::string out = urdf;
  for (const auto& [name, origin] : origins) {
    const Eigen::Vector3d t = origin.translation(), rpy = rollPitchYawFromRotation(origin.rotation());
    std::ostringstream element;
    element << std::setprecision(9) << "<origin xyz=\"" << t.x() << " " << t.y() << " " << t.z() << "\" rpy=\"" << rpy.x() << " " << rpy.y()
            << " " << rpy.z() << "\"/>";
    out = withJointElement(out, name, "origin", element.str(), what, "origin");
  }
  return out;
}

void writeCalibratedUrdf(const std::string& from, const std::string& to, const std::map<std::string, double>& offsets,
                         const std::map<std::string, Eigen::Isometry3d>& origins) {
  std::ifstream in(from);
  if (!in) throw InputError(from + ": cannot read the URDF");
  std::stringstream text;
  text << in.rdbuf();
  std::ofstream out(to);
  if (!out) throw InputError(to + ": cannot write the calibrated URDF");
  out << withJointOrigins(withJointOffsets(text.str(), offsets, from), origins, from);
  if (!out.flush()) throw InputError(to + ": write error");
}

}  // namespace vocal
