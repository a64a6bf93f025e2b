#pragma once
// One calibration session: the raw data of every sensor of a rig (clouds, scans, depth images, camera
// images) in, the target extracted from each, the still periods associated, the rig calibrated. What
// the calibrate_rig tool (from a bag) and the MsgCalibration nodelet (live) share.

#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "vocal/calibration/association/clock_offsets.h"
#include "vocal/calibration/association/hand_eye_association.h"
#include "vocal/calibration/association/joint_positions.h"
#include "vocal/calibration/association/still_target_association.h"
#include "vocal/calibration/extraction/lidar_ring_offsets.h"
#include "vocal/calibration/extraction/static_background.h"
#include "vocal/calibration/extraction/target_extraction.h"
#include "vocal/calibration/rig_description.h"
#include "vocal/calibration/solver/graph_calibration.h"
#include "vocal/core/image.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

struct SensorDataCounts {
  int received = 0;      // messages given to the session
  int target_found = 0;  // of which showed the target
  int only_background = 0;  // range sensors: board-shaped segments found, all of them static (room, furniture)
  int not_kept = 0;  // received while the session was full (SessionMemoryOptions): counted, nothing kept
  int views_with_corners_left_out = 0;  // cameras: views whose pose left misdetected corners out (observePattern)
};

// How much of a long session is held: what bounds a live session's memory (and a long bag's). Held is
// what each message leaves for the solve (the board's candidates' points, a camera's corners). Once it
// passes max_held_mb, the messages settled (stamped settle_seconds or more before the newest) that went
// into no still pose are let go - the target in motion, the room alone - and each still pose keeps per
// sensor its first max_pose_seconds, about max_pose_messages of them spread over that time but never
// further apart than a still run may bridge (StillnessOptions::max_gap) (a board left standing for
// minutes, or a 30 Hz depth camera's every frame, adds no geometry, only the same view again). When what is kept still fills three quarters of the budget the session is full: later
// messages are counted, not kept. A session that stays within the budget is never touched.
struct SessionMemoryOptions {
  double max_held_mb = 512.0;  // 0: no bound
  double settle_seconds = 10.0;
  double max_pose_seconds = 2.0;
  int max_pose_messages = 20;
};

struct SessionMemory {
  double held_mb = 0.0;
  std::size_t held_messages = 0;
  std::size_t let_go = 0;  // messages let go: settled and in no still pose, or beyond what a pose keeps
  bool full = false;
};

// What a range sensor's message gave: the board's candidates by shape, resolved once the whole session
// is known (the board is the candidate that is not static background).
struct RangeMessage {
  int sensor = -1;
  double stamp = 0.0;
  TargetSearch search;
  int chosen = -1;  // index into search.candidates once resolved, -1 when none was taken
  std::string rejection;  // why none was taken
  std::string check;      // which check refused the last candidate (TargetSearch::check, or "static background")
};

// Whether a lidar's ring offsets are applied, and why, in words for the user.
struct RingOffsetChoice {
  bool applied = false;
  std::string verdict;
  std::string warning;  // applied beyond the lidar's specification: what to check
};

class CalibrationSession {
 public:
  explicit CalibrationSession(RigDescription rig, TargetExtractionOptions extraction = {}, StillnessOptions stillness = {},
                              RingOffsetOptions ring_offsets = {}, SessionMemoryOptions memory = {});

  // Each returns whether the target was found (range sensors: a board-shaped segment; whether it is
  // static background is settled over the whole session). Throws InputError naming the sensor when it
  // has another type or the data is unusable (stamps are seconds).
  // lidar3d; `rings`: each point's ring as its driver numbers them (PointCloud2's `ring` field), or empty.
  // The driver's rings, where given, say which rings there are (else they are found by elevation).
  bool addCloud(int sensor, double stamp, const std::vector<Eigen::Vector3d>& cloud, const std::vector<int>& rings = {});
  bool addScan(int sensor, double stamp, const std::vector<Eigen::Vector3d>& scan);            // laser2d, in beam order
  bool addDepth(int sensor, double stamp, const DepthImage& depth, const PinholeCamera& camera);  // rgbd
  bool addImage(int sensor, double stamp, const ColorImage& image, const PinholeCamera& camera,
                const LensDistortion& distortion = {});  // camera, through its lens (camera_info's D)

  // The same in two steps, so that several messages can be searched at once (readCalibrationBag uses
  // every core): extract* finds what one message shows of the target without touching the session (safe
  // from several threads), take() adds it to the session, in arrival order. A lidar's spacing comes from
  // its first full cloud: prepareCloud each cloud, in order, before extractCloud. Each add* is
  // prepare (clouds), extract and take.
  struct Extraction {
    TargetSearch search;                   // range sensors: the board's candidates
    std::vector<Eigen::Vector3d> points;   // cameras: the pattern's corners (none: not seen)
    std::vector<PlaneMeasurement> planes;  // ... and its plane
    int corners_left_out = 0;              // ... misdetected corners its pose left out
  };
  void prepareCloud(int sensor, const std::vector<Eigen::Vector3d>& cloud, const std::vector<int>& rings = {});
  bool hasSpacing(int sensor) const { return lidar_spacing_.at(sensor).horizontal > 0.0; }  // extractCloud can search
  Extraction extractCloud(int sensor, const std::vector<Eigen::Vector3d>& cloud) const;
  Extraction extractScan(int sensor, const std::vector<Eigen::Vector3d>& scan) const;
  Extraction extractDepth(int sensor, const DepthImage& depth, const PinholeCamera& camera) const;
  Extraction extractImage(int sensor, const ColorImage& image, const PinholeCamera& camera, const LensDistortion& distortion = {}) const;
  bool take(int sensor, double stamp, Extraction extraction);

  // A hand-eye rig's tool frame (RigDescription::handEye) in the reference frame at `stamp`: a tf lookup,
  // at the rate tf gives it. Throws InputError for a rig without a moving frame or a pose that is not finite.
  void addToolPose(double stamp, const Eigen::Isometry3d& reference_from_tool);
  // The arm's still poses with the camera's views in each (a hand-eye rig; throws InputError otherwise);
  // for an arm whose tool comes from its joints, with each still pose's readings of its chain.
  HandEyeAssociation handEyeAssociation(const ToolStillnessOptions& options = {}) const;
  // An arm whose tool comes from its joints (HandEyeRig::from_joints): its chain, for HandEyeOptions::arm_joints.
  std::optional<ArmJoints> armJoints() const;
  // The hand-eye solve's options the rig gives: the arm's joints (armJoints) and the board's plate size.
  HandEyeOptions handEyeOptions() const;

  // A sensor_msgs/JointState: each named joint's position at `stamp` (joints the rig does not name are
  // ignored; a reading that is not finite is skipped); for an arm whose tool comes from its joints, the
  // tool's pose at `stamp` when the message reads every joint of its chain (as addToolPose). Throws InputError when names and
  // positions differ in number or the stamp is not finite.
  void addJointState(double stamp, const std::vector<std::string>& names, const std::vector<double>& positions);
  // The joints' readings kept per joint of the rig (rig().joints), and what attaching them to the still
  // poses' views kept and dropped (JointPositionCounts).
  std::size_t jointReadings() const;
  JointPositionCounts jointPositionCounts() const;

  // Still periods associated (a sensor behind joints keeps the views where its joints were still, with their
  // positions: attachJointPositions), then calibrateRig with the rig's reference sensor and pose. Throws
  // InputError naming the sensor (no target seen, not connected, degenerate) as calibrateRig does, and
  // for a sensor that saw the target but in no still pose, why (its spacing, the run it would need).
  CalibrationResult calibrate(CalibrationOptions options = {}) const;
  std::vector<TargetObservation> associatedObservations() const;
  // The same on observations already associated (callers that also show or count them).
  CalibrationResult calibrate(const std::vector<TargetObservation>& associated, CalibrationOptions options = {}) const;
  // The options calibrate() solves with: the rig's reference sensor and pose, its board's size for
  // edges (what jackknifeOverPoses, pose_jackknife.h, re-solves with).
  CalibrationOptions calibrationOptions(CalibrationOptions options) const;

  const RigDescription& rig() const { return rig_; }
  std::vector<SensorDataCounts> counts() const;
  SessionMemory memory() const;
  // memory() in words: what is held against the budget, what was let go, whether the session is full.
  std::string memorySummary() const;
  // Every range sensor's message in arrival order, with the candidate taken and why none was.
  std::vector<RangeMessage> rangeMessages() const;
  int sensorIndex(const std::string& name) const;  // -1 when the rig has no such sensor
  // Per sensor, a 3D lidar's ring offsets estimated from the room planes of its clouds so far, with
  // whether its board points are corrected by them (RingOffsets::applied, verdict): those within the
  // lidar's specification are, until chooseRingOffsets has decided otherwise (those beyond it are not
  // until it has decided they are); none for other sensors,
  // with ring offsets off, or before a cloud; a lidar without rings (a solid-state, non-repeating pattern)
  // gets no offsets and a verdict saying so.
  std::vector<std::optional<RingOffsets>> ringOffsets() const;
  // Per 3D lidar whose offsets the room's planes estimated (within its specification or not): the rig
  // solved with and without them, each leaving out one still pose at a time, and the offsets kept only
  // when they predict the lidar's held-out board views better (heldOutBoardFit, pose_jackknife.h); the
  // verdict says which and by how much, and offsets kept beyond the specification carry a warning. Holds until the next cloud. Returns ringOffsets(). In three steps for a caller that holds a
  // lock over the session (the re-solves take seconds): ringOffsetTrials (cheap), judgeRingOffsets (the
  // re-solves, no session state), recordRingOffsetChoice.
  std::vector<std::optional<RingOffsets>> chooseRingOffsets(const CalibrationOptions& options);
  struct RingOffsetTrial {
    int sensor = -1;
    RingOffsets offsets;                           // as the room's planes gave them
    std::vector<TargetObservation> without, with;  // the still poses associated without and with its offsets
  };
  std::vector<RingOffsetTrial> ringOffsetTrials() const;
  void recordRingOffsetChoice(int sensor, RingOffsetChoice choice);
  // Each sensor's clock against the reference sensor's, from its still runs (clock_offsets.h): those
  // applied are taken off its stamps before every association.
  std::vector<ClockOffset> clockOffsets() const;
  void setClockOffsetOptions(const ClockOffsetOptions& options) { clock_offset_options_ = options; }

 private:
  const RigSensorDescription& checkSensor(int sensor, SensorType expected, const char* data) const;
  // Still poses (associateStillTarget), the views of sensors behind joints with their positions (attachJointPositions).
  std::vector<TargetObservation> associate(std::vector<TimedObservation> timed, JointPositionCounts* counts = nullptr) const;
  bool record(int sensor, double stamp, std::vector<Eigen::Vector3d> points, std::vector<PlaneMeasurement> planes);
  bool recordRange(int sensor, double stamp, TargetSearch search);
  TargetExtractionOptions extractionFor(int sensor) const;
  // Whether a message holding `bytes` may be kept within the memory budget (SessionMemoryOptions): past
  // it, what no still pose uses is let go first; false once the session is full.
  bool roomFor(std::size_t bytes);
  void letGoOfWhatNoStillPoseUses();
  // The offsets as estimated, each applied when within its lidar's specification (no choice yet).
  std::vector<std::optional<RingOffsets>> estimatedRingOffsets() const;
  // Every observation: cameras' as recorded, range sensors' candidates resolved against the background,
  // each lidar's corrected by its ring offsets where they are applied.
  std::vector<TimedObservation> timedObservations() const;
  // `sample` > 0: each range view's points a sample of at most that many (TimedObservation::point_count).
  std::vector<TimedObservation> timedObservations(const std::vector<std::optional<RingOffsets>>& offsets, std::size_t sample = 0) const;
  // Per range message, the candidate taken (-1: none): computed once per new message, as diagnostics
  // ask for the counts every second of a long session.
  const std::vector<int>& chosenCandidates() const;

  RigDescription rig_;
  TargetExtractionOptions extraction_;
  StillnessOptions stillness_;
  ClockOffsetOptions clock_offset_options_;
  std::vector<SensorDataCounts> counts_;
  std::vector<TimedObservation> observations_;  // cameras
  std::optional<HandEyeRig> arm_;                // rig_.handEye(), once
  std::vector<std::vector<int>> still_links_;    // ... its links sensors sit on, each once: still with the tool in a still pose
  JointedMounts mounts_;                         // rig_.jointedMounts(), once
  std::vector<std::vector<JointReading>> joint_readings_;  // per joint of the rig, in time order
  std::unordered_map<std::string, int> joint_index_;       // a joint's name -> its index in the rig
  JointStillnessOptions joint_stillness_;
  std::vector<FramePoseSample> tool_poses_;      // a hand-eye rig's tool frame, as tf gave it
  // A range message as kept until the solve: its candidates' points (most of a session's memory) in
  // floats, whose micrometres at lidar range are far below any sensor's noise; converted back to
  // RangeMessage / TimedObservation when asked for.
  struct StoredCandidate {
    std::vector<Eigen::Vector3f> points, outline;
    double mismatch = 0.0;
  };
  struct StoredRangeMessage {
    int sensor = -1;
    double stamp = 0.0;
    std::vector<StoredCandidate> candidates;
    std::string rejection, check;  // TargetSearch's, when there are no candidates
  };
  static std::size_t heldBytes(const StoredRangeMessage& message);
  std::vector<StoredRangeMessage> range_messages_;
  std::vector<std::vector<StaticBackground::Summary>> candidate_summaries_;  // per range message
  mutable std::vector<int> chosen_;  // chosenCandidates(), valid while its size matches range_messages_
  std::vector<StaticBackground> backgrounds_;  // per sensor
  std::vector<ScanSpacing> lidar_spacing_;     // per sensor, estimated from its first full cloud
  RingOffsetOptions ring_offset_options_;
  std::vector<std::optional<RingOffsetEstimator>> ring_offsets_;  // per sensor: lidars, from their first full cloud
  // Per sensor, chooseRingOffsets's decision until the next cloud.
  std::vector<std::optional<RingOffsetChoice>> ring_offset_choice_;
  SessionMemoryOptions memory_options_;
  std::size_t held_bytes_ = 0;  // of observations_ and range_messages_
  std::size_t let_go_ = 0;
  bool full_ = false;
  double newest_stamp_ = -std::numeric_limits<double>::infinity();
};

// Judges one lidar's trial (CalibrationSession::ringOffsetTrials): the held-out board views predicted
// with and without its offsets (`options`: CalibrationSession::calibrationOptions), the offsets applied
// when they predict no worse, or when no pose lets them be checked.
RingOffsetChoice judgeRingOffsets(const std::vector<SensorSpec>& sensors, const CalibrationSession::RingOffsetTrial& trial,
                                  const CalibrationOptions& options);

}  // namespace vocal
