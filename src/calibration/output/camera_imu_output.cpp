#include "vocal/calibration/output/camera_imu_output.h"

#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>

#include "vocal/calibration/output/calibration_output.h"
#include "vocal/core/errors.h"

namespace vocal {

namespace {
std::string vector3(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << std::setprecision(9) << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return out.str();
}

std::string pose(const Eigen::Isometry3d& p, const std::string& indent) {
  const Eigen::Quaterniond q(p.rotation());
  std::ostringstream out;
  out << std::setprecision(9) << indent << "translation: " << vector3(p.translation()) << "\n"
      << indent << "rotation: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n";
  return out.str();
}

const std::string& parentFrame(const ImuCalibrationOutput& imu, const std::string& reference_frame) {
  return imu.parent_frame.empty() ? reference_frame : imu.parent_frame;
}
}  // namespace

std::string imuCalibrationYaml(const std::vector<ImuCalibrationOutput>& imus, const std::string& reference_frame) {
  std::ostringstream out;
  out << std::setprecision(9) << "imus:  # camera-IMU calibration from the waved session: each IMU in its parent, its camera's\n";
  for (const ImuCalibrationOutput& imu : imus) {
    const CameraImuResult& r = imu.result;
    out << "  - name: " << imu.name << "\n"
        << "    frame_id: " << imu.frame_id << "\n"
        << "    parent: " << parentFrame(imu, reference_frame) << "\n";
    if (imu.rig_from_imu) out << pose(*imu.rig_from_imu, "    ");
    out << "    camera: " << imu.camera_name << "\n"
        << "    camera_in_imu:  # x_imu = T x_camera (" << imu.camera_frame << " in " << imu.frame_id << ")\n"
        << pose(r.camera_in_imu, "      ")
        << "      translation_stddev: " << vector3(r.sigma.head<3>()) << "  # m, along the IMU frame's axes\n"
        << "      rotation_stddev: " << vector3(r.sigma.tail<3>()) << "  # rad, about them\n"
        << "    time_offset: " << r.time_offset << "  # s: IMU stamp = camera stamp + time_offset (Kalibr's timeshift_cam_imu)\n"
        << "    time_offset_stddev: " << r.time_offset_sigma << "\n"
        << "    gyro_bias: " << vector3(r.gyro_bias) << "  # rad/s, the session's mean\n"
        << "    accelerometer_bias: " << vector3(r.accel_bias) << "  # m/s^2\n"
        << "    residuals: {gyro_rms: " << r.gyro_rms << ", accelerometer_rms: " << r.accel_rms << ", view_translation_rms: "
        << r.view_translation_rms << ", view_rotation_rms: " << r.view_rotation_rms << "}\n"
        << "    views: " << r.views << "\n"
        << "    imu_samples: " << r.imu_samples << "\n"
        << "    published: " << (imu.withheld.empty() ? "true" : "false") << "\n";
    if (!imu.withheld.empty()) out << "    withheld_because: " << yamlQuoted(imu.withheld) << "\n";
  }
  return out.str();
}

namespace {
// Per IMU, `published(imu)`, or where it is withheld a comment saying why (indented by `indent`).
std::string perImu(const std::vector<ImuCalibrationOutput>& imus, const std::string& indent,
                   const std::function<std::string(const ImuCalibrationOutput&)>& published) {
  std::string out;
  for (const ImuCalibrationOutput& imu : imus) {
    const bool placed = imu.withheld.empty() && imu.rig_from_imu;
    out += placed ? published(imu) : indent + "<!-- " + imu.frame_id + " withheld: " + imu.withheld + " (see calibration.yaml) -->\n";
  }
  return out;
}
}  // namespace

std::string imuUrdfJoints(const std::vector<ImuCalibrationOutput>& imus, const std::string& reference_frame) {
  return perImu(imus, "", [&](const ImuCalibrationOutput& imu) {
    return urdfFixedJoint(parentFrame(imu, reference_frame), imu.frame_id, *imu.rig_from_imu);
  });
}

std::string imuStaticTransformNodes(const std::vector<ImuCalibrationOutput>& imus, const std::string& reference_frame) {
  return perImu(imus, "  ", [&](const ImuCalibrationOutput& imu) {
    return staticTransformNode(imu.name + "_extrinsic", parentFrame(imu, reference_frame), imu.frame_id, *imu.rig_from_imu);
  });
}

void writeKalibrCamchain(const std::string& path, const std::vector<ImuCalibrationOutput>& imus) {
  std::ofstream file(path);
  if (!file) throw InputError(path + ": cannot write Kalibr's camchain-imucam.yaml");
  file << std::setprecision(12);
  for (std::size_t i = 0; i < imus.size(); ++i) {
    const ImuCalibrationOutput& imu = imus[i];
    const Eigen::Matrix4d t_cam_imu = imu.result.camera_in_imu.inverse().matrix();
    file << "cam" << i << ":\n  T_cam_imu:  # IMU '" << imu.name << "' (" << imu.frame_id << ") to camera '" << imu.camera_name << "' ("
         << imu.camera_frame << ")\n";
    for (int r = 0; r < 4; ++r) {
      file << "  - [" << t_cam_imu(r, 0) << ", " << t_cam_imu(r, 1) << ", " << t_cam_imu(r, 2) << ", " << t_cam_imu(r, 3) << "]\n";
    }
    // Kalibr's lens names; rational_polynomial has none there.
    std::vector<double> d = imu.lens.coefficients;
    std::string model = "radtan";
    if (imu.lens.model == DistortionModel::kEquidistant) model = "equidistant";
    if (imu.lens.model == DistortionModel::kRationalPolynomial) model = "rational_polynomial  # not a Kalibr model";
    if (imu.lens.model == DistortionModel::kPlumbBob && d.size() > 4) d.resize(4);  // radtan: k1 k2 p1 p2
    if (imu.lens.isNone()) d.assign(4, 0.0);
    file << "  cam_overlaps: []\n  camera_model: pinhole\n  distortion_coeffs: [";
    for (std::size_t k = 0; k < d.size(); ++k) file << (k ? ", " : "") << d[k];
    file << "]\n  distortion_model: " << model << "\n"
         << "  intrinsics: [" << imu.camera.fx << ", " << imu.camera.fy << ", " << imu.camera.cx << ", " << imu.camera.cy << "]\n"
         << "  resolution: [" << imu.camera.width << ", " << imu.camera.height << "]\n"
         << "  rostopic: " << imu.camera_topic << "\n"
         << "  timeshift_cam_imu: " << imu.result.time_offset << "  # t_imu = t_cam + shift\n";
  }
  if (!file.flush()) throw InputError(path + ": write error");
}

}  // namespace vocal
