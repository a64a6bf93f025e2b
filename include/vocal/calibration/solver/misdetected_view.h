#pragma once
// How far a camera view's board may lie from where the started rig puts it before its whole PnP pose is
// taken for a misdetection (a pattern found shifted by a square, something else seen): the arm's graph
// leaves such a view out (HandEyeResult::misdetected_views), the still-pose graph holds it by its plane
// only (CalibrationResult::misdetected_views). Either start is within millimetres; a view held at its
// PnP covariance (tens of micrometres) that far off would pull every unknown towards it.

namespace vocal {

constexpr double kMisdetectedViewDistance = 0.015;  // metres
constexpr double kMisdetectedViewAngle = 0.05;      // radians

}  // namespace vocal
