#include "vocal/core/se3.h"

#include <algorithm>
#include <cmath>

namespace vocal {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

namespace {
// V = I + B skew(w) + C skew(w)^2, the left Jacobian that couples rotation into translation.
Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d W = skew(w);
  double b, c;
  if (theta < 1e-5) {
    const double t2 = theta * theta;
    b = 0.5 - t2 / 24.0;
    c = 1.0 / 6.0 - t2 / 120.0;
  } else {
    b = (1.0 - std::cos(theta)) / (theta * theta);
    c = (theta - std::sin(theta)) / (theta * theta * theta);
  }
  return Eigen::Matrix3d::Identity() + b * W + c * W * W;
}
}  // namespace

Eigen::Matrix3d so3Exp(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  // First-order quaternion near zero; AngleAxis cannot normalise a zero axis.
  if (theta < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized().toRotationMatrix();
  return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
}

Eigen::Vector3d so3Log(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return aa.axis() * aa.angle();
}

Eigen::Isometry3d se3Exp(const Vector6d& twist) {
  const Eigen::Vector3d w = twist.tail<3>();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = so3Exp(w);
  pose.translation() = leftJacobian(w) * twist.head<3>();
  return pose;
}

Vector6d se3Log(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d w = so3Log(pose.rotation());
  Vector6d twist;
  twist.head<3>() = leftJacobian(w).inverse() * pose.translation();
  twist.tail<3>() = w;
  return twist;
}

Eigen::Isometry3d poseFromTranslationQuaternion(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = t;
  return pose;
}

Eigen::Isometry3d chordalMean(const std::vector<Eigen::Isometry3d>& poses) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  for (const Eigen::Isometry3d& p : poses) {
    sum += p.linear();
    translation += p.translation();
  }
  Eigen::Isometry3d mean = Eigen::Isometry3d::Identity();
  if (poses.empty()) return mean;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d rotation = svd.matrixU() * svd.matrixV().transpose();
  if (rotation.determinant() < 0) rotation = svd.matrixU() * Eigen::Vector3d(1, 1, -1).asDiagonal() * svd.matrixV().transpose();
  mean.linear() = rotation;
  mean.translation() = translation / static_cast<double>(poses.size());
  return mean;
}

double rotationAngle(const Eigen::Isometry3d& pose) {
  const double c = 0.5 * (pose.linear().trace() - 1.0);
  // acos loses precision near 0; atan2 of |sin| and cos does not.
  const Eigen::Matrix3d R = pose.linear();
  const Eigen::Vector3d axis_sin(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axis_sin.norm(), std::clamp(c, -1.0, 1.0));
}

Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double alpha) {
  const Eigen::Quaterniond qa(a.rotation());
  const Eigen::Quaterniond qb(b.rotation());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = qa.slerp(alpha, qb).toRotationMatrix();
  pose.translation() = (1.0 - alpha) * a.translation() + alpha * b.translation();
  return pose;
}

Eigen::Matrix3d rotationFromRollPitchYaw(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d rollPitchYawFromRotation(const Eigen::Matrix3d& r) {
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  if (std::abs(r(2, 0)) > 1.0 - 1e-12) {
    // Gimbal lock: roll and yaw turn about one axis; all of it given to yaw.
    return {0.0, pitch, std::atan2(-r(0, 1), r(1, 1))};
  }
  return {std::atan2(r(2, 1), r(2, 2)), pitch, std::atan2(r(1, 0), r(0, 0))};
}

Eigen::Matrix3d bodyFromOpticalRotation() {
  Eigen::Matrix3d R;
  R << 0, 0, 1,  //
      -1, 0, 0,  //
      0, -1, 0;
  return R;
}

Matrix6d adjoint(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d R = pose.rotation();
  Matrix6d ad = Matrix6d::Zero();
  ad.topLeftCorner<3, 3>() = R;
  ad.topRightCorner<3, 3>() = skew(pose.translation()) * R;
  ad.bottomRightCorner<3, 3>() = R;
  return ad;
}

}  // namespace vocal
