#pragma once
// SE(3) helpers on Eigen. Twists are ordered [translation; rotation] (v, w).

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vocal {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

Eigen::Matrix3d skew(const Eigen::Vector3d& v);

// Exponential and logarithm maps of SO(3): a rotation vector (axis times angle, radians) and back.
Eigen::Matrix3d so3Exp(const Eigen::Vector3d& w);
Eigen::Vector3d so3Log(const Eigen::Matrix3d& rotation);

// Exponential and logarithm maps of SE(3) (closed form, stable near zero rotation).
Eigen::Isometry3d se3Exp(const Vector6d& twist);
Vector6d se3Log(const Eigen::Isometry3d& pose);

// Adjoint of a pose on twists [v; w]: se3Exp(adjoint(T) x) = T se3Exp(x) T^-1. Moves a twist (or its
// covariance, Ad C Ad^T) from the frame `pose` maps from into the frame it maps to.
Matrix6d adjoint(const Eigen::Isometry3d& pose);

// Pose from a translation and a quaternion (x y z w order as in TUM files); the quaternion is
// normalised, so callers must reject zero or non-finite ones first.
Eigen::Isometry3d poseFromTranslationQuaternion(const Eigen::Vector3d& t, const Eigen::Quaterniond& q);

// Rotation angle of a pose's rotation in radians, in [0, pi].
double rotationAngle(const Eigen::Isometry3d& pose);

// The chordal mean of poses: the rotation nearest the sum of their rotation matrices (SVD), the mean
// translation; the identity for none.
Eigen::Isometry3d chordalMean(const std::vector<Eigen::Isometry3d>& poses);

// Interpolates between poses: linear in translation, slerp in rotation; alpha in [0, 1].
Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double alpha);

// Rotation from roll (about x), pitch (about y), yaw (about z): R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d rotationFromRollPitchYaw(double roll, double pitch, double yaw);
// Its inverse, (roll, pitch, yaw) with pitch in [-pi/2, pi/2] and the others in [-pi, pi] (URDF's rpy: a
// rotation near the identity reads near zero, not near pi as Eigen's eulerAngles may give it).
Eigen::Vector3d rollPitchYawFromRotation(const Eigen::Matrix3d& rotation);

// Maps the REP-103 body frame (x forward, y left, z up) to the optical frame (z forward, x right,
// y down): R_body_optical, whose columns are the optical axes in body coordinates.
Eigen::Matrix3d bodyFromOpticalRotation();

}  // namespace vocal
