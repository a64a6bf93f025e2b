#include "vocal/calibration/association/clock_offsets.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "vocal/calibration/point_statistics.h"

namespace vocal {

namespace {
// The runs of `shifted` (moved by `shift` seconds) that lie over a run of `over`: for each, the
// differences of its matched run's start and end from its own (unshifted).
struct RunMatch {
  int count = 0;
  double misfit = 0.0;  // seconds: how far the matched starts and ends lie from the shift, summed
  std::vector<double> begins, ends;
  std::vector<int> matched;  // per shifted run, the index of the run of `over` it lies over, -1 for none
};

RunMatch matchRuns(const std::vector<StillSpan>& shifted, const std::vector<StillSpan>& over, double shift) {
  RunMatch match;
  match.matched.assign(shifted.size(), -1);
  for (std::size_t i = 0; i < shifted.size(); ++i) {
    const StillSpan& a = shifted[i];
    const double begin = a.begin + shift, end = a.end + shift;
    const StillSpan* best = nullptr;
    double best_overlap = 0.0;
    for (const StillSpan& b : over) {
      const double overlap = std::min(end, b.end) - std::max(begin, b.begin);
      if (overlap > best_overlap) best_overlap = overlap, best = &b;
    }
    // Half the shorter run: a run cut in two by a hand over the board still lies over its pose.
    if (!best || best_overlap < 0.5 * std::min(end - begin, best->end - best->begin)) continue;
    ++match.count;
    match.matched[i] = static_cast<int>(best - over.data());
    match.begins.push_back(best->begin - a.begin);
    match.ends.push_back(best->end - a.end);
    match.misfit += std::abs(best->begin - begin) + std::abs(best->end - end);
  }
  return match;
}

// The shift from a match: the medians of the starts' and the ends' differences, averaged.
double refinedShift(const RunMatch& match) { return 0.5 * (median(match.begins) + median(match.ends)); }

// Its standard error: the differences' MAD as a standard deviation, over the 2n of them.
double shiftSigma(const RunMatch& match) {
  const double begins = median(match.begins), ends = median(match.ends);
  std::vector<double> deviations;
  for (double d : match.begins) deviations.push_back(std::abs(d - begins));
  for (double d : match.ends) deviations.push_back(std::abs(d - ends));
  return 1.4826 * median(deviations) / std::sqrt(static_cast<double>(deviations.size()));
}

// One sensor's messages in time order: stamp and where it saw the board's centre.
struct CentreTrack {
  std::vector<double> stamps;
  std::vector<Eigen::Vector3d> centres;

  // The median centre over [begin, end]; false when no message lies there.
  bool stillCentre(double begin, double end, Eigen::Vector3d* centre) const {
    std::vector<double> x, y, z;
    for (std::size_t i = 0; i < stamps.size(); ++i) {
      if (stamps[i] < begin || stamps[i] > end) continue;
      x.push_back(centres[i].x()), y.push_back(centres[i].y()), z.push_back(centres[i].z());
    }
    if (x.empty()) return false;
    *centre = Eigen::Vector3d(median(x), median(y), median(z));
    return true;
  }

  // When the board, leaving `from` for `to` between `begin` and `end`, was half way: its distance from
  // `from` over theirs (a frame-free measure: any sensor sees the same share at the same moment), the
  // crossing of one half interpolated between the two messages around it. NaN when none crosses.
  double halfWay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double begin, double end) const {
    const double apart = (to - from).norm();
    double last_stamp = begin, last_share = 0.0;
    for (std::size_t i = 0; i < stamps.size(); ++i) {
      if (stamps[i] <= begin) continue;
      if (stamps[i] >= end) break;
      const double share = (centres[i] - from).norm() / apart;
      if (share >= 0.5) return last_stamp + (stamps[i] - last_stamp) * (0.5 - last_share) / std::max(share - last_share, 1e-9);
      last_stamp = stamps[i], last_share = share;
    }
    return std::numeric_limits<double>::quiet_NaN();
  }
};

std::vector<CentreTrack> centreTracks(std::size_t sensors, const std::vector<TimedObservation>& observations) {
  std::vector<const TimedObservation*> sorted;
  for (const TimedObservation& o : observations)
    if (!o.points.empty()) sorted.push_back(&o);
  std::stable_sort(sorted.begin(), sorted.end(), [](const TimedObservation* a, const TimedObservation* b) { return a->stamp < b->stamp; });
  std::vector<CentreTrack> tracks(sensors);
  for (const TimedObservation* o : sorted) {
    tracks[o->sensor].stamps.push_back(o->stamp);
    tracks[o->sensor].centres.push_back(centroidOf(o->points));
  }
  return tracks;
}

// The shift refined by the moves between consecutive still poses both sensors held (`runs`: the runs
// matched): the moment each saw the board half way from one to the next, differenced; the median over
// the moves, with its standard error. False with fewer than `least` moves of at least 5 cm.
bool refineByMoves(const std::vector<StillSpan>& shifted, const std::vector<StillSpan>& over, const RunMatch& runs,
                   const CentreTrack& shifted_track, const CentreTrack& over_track, int least, double* refined, double* sigma) {
  const std::vector<int>& matched = runs.matched;
  std::vector<double> differences;
  constexpr double kLeastMove = 0.05;  // metres: a smaller move's half way is lost in the sensors' noise
  for (std::size_t i = 0; i + 1 < shifted.size(); ++i) {
    const int j = matched[i];
    if (j < 0 || matched[i + 1] != j + 1) continue;
    const StillSpan &a0 = shifted[i], &a1 = shifted[i + 1], &b0 = over[j], &b1 = over[j + 1];
    Eigen::Vector3d a_from, a_to, b_from, b_to;
    if (!shifted_track.stillCentre(a0.begin, a0.end, &a_from) || !shifted_track.stillCentre(a1.begin, a1.end, &a_to) ||
        !over_track.stillCentre(b0.begin, b0.end, &b_from) || !over_track.stillCentre(b1.begin, b1.end, &b_to))
      continue;
    if ((a_to - a_from).norm() < kLeastMove || (b_to - b_from).norm() < kLeastMove) continue;
    const double a_half = shifted_track.halfWay(a_from, a_to, a0.end, a1.begin);
    const double b_half = over_track.halfWay(b_from, b_to, b0.end, b1.begin);
    if (std::isfinite(a_half) && std::isfinite(b_half)) differences.push_back(b_half - a_half);
  }
  if (static_cast<int>(differences.size()) < least) return false;
  *refined = median(differences);
  std::vector<double> deviations;
  for (double d : differences) deviations.push_back(std::abs(d - *refined));
  *sigma = 1.4826 * median(deviations) / std::sqrt(static_cast<double>(differences.size()));
  return true;
}

// Each run's board centre (the median over its span), where the sensor saw the board in it.
std::vector<std::optional<Eigen::Vector3d>> runCentres(const std::vector<StillSpan>& spans, const CentreTrack& track) {
  std::vector<std::optional<Eigen::Vector3d>> centres;
  for (const StillSpan& span : spans) {
    Eigen::Vector3d centre;
    centres.push_back(track.stillCentre(span.begin, span.end, &centre) ? std::optional<Eigen::Vector3d>(centre) : std::nullopt);
  }
  return centres;
}

// How far the distances between the board's centres at the matched runs' poses, pair by pair, differ
// between the two sensors (metres, the median): a distance is the same in every sensor's frame, so runs
// laid over the wrong poses (shifted by whole poses in an evenly paced session) show in it. NaN with
// fewer than three pairs.
double centreDistanceMisfit(const RunMatch& match, const std::vector<std::optional<Eigen::Vector3d>>& shifted,
                            const std::vector<std::optional<Eigen::Vector3d>>& over) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> centres;
  for (std::size_t i = 0; i < shifted.size(); ++i) {
    const int j = match.matched[i];
    if (j >= 0 && shifted[i] && over[j]) centres.emplace_back(*shifted[i], *over[j]);
  }
  std::vector<double> misfits;
  for (std::size_t i = 0; i < centres.size(); ++i)
    for (std::size_t k = i + 1; k < centres.size(); ++k)
      misfits.push_back(std::abs((centres[i].first - centres[k].first).norm() - (centres[i].second - centres[k].second).norm()));
  return misfits.size() < 3 ? std::numeric_limits<double>::quiet_NaN() : median(misfits);
}

// The board's moves between poses tell the right association from one a whole pose off only over four
// runs or more (six distances): three give a median of three, as likely small by chance.
constexpr int kLeastWitnessRuns = 4;

// A shift's association of the sensor's runs with the reference's.
struct ShiftHypothesis {
  double shift = 0.0;
  RunMatch match;
  double distance_misfit = 0.0;  // centreDistanceMisfit's
};
}  // namespace

std::vector<ClockOffset> estimateClockOffsets(const std::vector<SensorSpec>& sensors, const std::vector<TimedObservation>& observations,
                                              int reference, const StillnessOptions& stillness, const ClockOffsetOptions& options) {
  if (!options.enabled) return {};
  std::vector<std::vector<StillSpan>> runs(sensors.size());
  for (const StillSpan& span : stillSpans(sensors, observations, stillness)) runs[span.sensor].push_back(span);
  if (reference < 0 || reference >= static_cast<int>(sensors.size()) || static_cast<int>(runs[reference].size()) < options.least_runs) {
    reference = static_cast<int>(std::max_element(runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); }) -
                                 runs.begin());
  }
  std::vector<ClockOffset> offsets;
  const std::vector<StillSpan>& over = runs[reference];
  const std::vector<CentreTrack> tracks = centreTracks(sensors.size(), observations);
  const std::vector<std::optional<Eigen::Vector3d>> over_centres = runCentres(over, tracks[reference]);
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    if (static_cast<int>(s) == reference || runs[s].empty()) continue;
    ClockOffset offset;
    offset.sensor = static_cast<int>(s);
    offset.reference = reference;
    const std::vector<std::optional<Eigen::Vector3d>> centres = runCentres(runs[s], tracks[s]);
    const auto hypothesis = [&](double shift) {
      ShiftHypothesis h{shift, matchRuns(runs[s], over, shift), 0.0};
      h.distance_misfit = centreDistanceMisfit(h.match, centres, over_centres);
      return h;
    };
    const ShiftHypothesis stamped = hypothesis(0.0);
    const RunMatch& unshifted = stamped.match;
    offset.runs_unshifted = unshifted.count;
    offset.distance_misfit_stamped = stamped.distance_misfit;
    // Every shift that lays a start on a start or an end on an end.
    // (To 10 ms, once each: a long session's thousands of run pairs give at most a thousand shifts.)
    std::vector<double> shifts{0.0};
    for (const StillSpan& a : runs[s])
      for (const StillSpan& b : over)
        for (const double shift : {b.begin - a.begin, b.end - a.end})
          if (std::abs(shift) <= options.max_offset) shifts.push_back(0.01 * std::round(100.0 * shift));
    std::sort(shifts.begin(), shifts.end());
    shifts.erase(std::unique(shifts.begin(), shifts.end()), shifts.end());
    std::vector<ShiftHypothesis> hypotheses;
    double least_misfit = std::numeric_limits<double>::infinity();
    for (const double shift : shifts) {
      hypotheses.push_back(hypothesis(shift));
      const ShiftHypothesis& h = hypotheses.back();
      if (h.match.count >= kLeastWitnessRuns && h.distance_misfit < least_misfit) least_misfit = h.distance_misfit;
    }
    // In an evenly paced session a shift by whole poses lays runs over the neighbouring poses' (a sensor
    // that found the board in only some, or something else in others, may then lay more of them over): the
    // board's moves between those poses then disagree with the reference's far more than the right
    // association's (measured: 107 mm against 16 mm; a true offset's 20 mm, a 2D laser's line centres 40 mm).
    constexpr double kMisfitGrowth = 2.0, kMisfitSlack = 0.02;  // -, metres
    const auto wrongPoses = [&](const ShiftHypothesis& h) { return h.distance_misfit > kMisfitGrowth * least_misfit + kMisfitSlack; };
    // The shift that lays the most runs over the reference's, the closest fit among equals, of those whose
    // poses are the reference's.
    const auto better = [](const ShiftHypothesis& a, const ShiftHypothesis& b) {
      return a.match.count > b.match.count || (a.match.count == b.match.count && a.match.misfit < b.match.misfit);
    };
    const ShiftHypothesis* chosen = wrongPoses(stamped) ? nullptr : &stamped;
    const ShiftHypothesis* most = &stamped;
    for (const ShiftHypothesis& h : hypotheses) {
      if (better(h, *most)) most = &h;
      if (!wrongPoses(h) && (!chosen || better(h, *chosen))) chosen = &h;
    }
    if (!chosen) chosen = most;
    if (most != chosen && most->match.count > chosen->match.count && std::abs(most->shift) >= options.least_offset) {
      char why[320];
      std::snprintf(why, sizeof(why),
                    "stamps %.2f s %s would lay %d of its still runs over the reference's, but the board's moves between "
                    "their poses disagree with the reference's by %.0f mm: the wrong poses, not taken",
                    std::abs(most->shift), most->shift <= 0.0 ? "late" : "early", most->match.count, 1000 * most->distance_misfit);
      offset.refused = why;
    }
    double best_shift = chosen->shift;
    RunMatch best = chosen->match;
    bool runs_shifted = false;
    if (best.count > 0) {
      best_shift = refinedShift(best);
      RunMatch refined = matchRuns(runs[s], over, best_shift);
      if (refined.count >= best.count) best = std::move(refined), best_shift = refinedShift(best);
      offset.sigma = shiftSigma(best);
      // The runs themselves shifted, beyond the least offset and their own noise.
      runs_shifted = std::abs(best_shift) >= std::max(options.least_offset, 3.0 * offset.sigma);
      // The runs' starts and ends lag by how still each sensor's noise lets a run be: the moves between
      // poses time the board alike for every sensor. Taken where they agree with the runs.
      double moved = 0.0, sigma = 0.0;
      if (refineByMoves(runs[s], over, matchRuns(runs[s], over, best_shift), tracks[s], tracks[reference], options.least_runs, &moved,
                        &sigma) &&
          std::abs(moved - best_shift) <= std::max(options.least_offset, 3.0 * offset.sigma)) {
        best_shift = moved;
        offset.sigma = sigma;
      }
    }
    offset.late = -best_shift;
    offset.runs = best.count;
    offset.distance_misfit = centreDistanceMisfit(matchRuns(runs[s], over, best_shift), centres, over_centres);
    // Applied only where the stamps as given lose still poses, or lay runs over the wrong ones: an offset
    // association tolerates is left alone, and a sensor moving on its own (on a head the rig does not
    // describe), whose runs start and end out of step with the board's - its own moves timed alike - is
    // not taken for a clock.
    // A shift must also lay enough runs over for the board's moves to vouch for its poses: with a reference
    // that held the board still at four poses of fifteen, 5 s laid 3 runs of a lidar on time over them
    // where its stamps laid 2, each a pose off.
    offset.applied = runs_shifted && best.count >= std::max(options.least_runs, kLeastWitnessRuns) &&
                     (best.count > unshifted.count || wrongPoses(stamped)) &&
                     std::abs(offset.late) >= std::max(options.least_offset, 3.0 * offset.sigma);
    offsets.push_back(offset);
  }
  return offsets;
}

void applyClockOffsets(const std::vector<ClockOffset>& offsets, std::vector<TimedObservation>* observations) {
  for (const ClockOffset& offset : offsets) {
    if (!offset.applied) continue;
    for (TimedObservation& o : *observations)
      if (o.sensor == offset.sensor) o.stamp -= offset.late;
  }
}

std::string describeClockOffset(const ClockOffset& offset, const std::vector<SensorSpec>& sensors) {
  char line[400];
  std::snprintf(line, sizeof(line), "sensor '%s' stamps %.3f s %s against '%s' (%d of its still runs over the reference's, %d as stamped; +-%.3f s)",
                sensors[offset.sensor].name.c_str(), std::abs(offset.late), offset.late >= 0.0 ? "late" : "early",
                sensors[offset.reference].name.c_str(), offset.runs, offset.runs_unshifted, offset.sigma);
  std::string text = line;
  if (offset.applied) text += ": its stamps are corrected before association (is its clock synchronised? PTP, chrony, the driver's time source)";
  if (!offset.refused.empty()) text += (offset.applied ? "; " : ": ") + offset.refused;
  return text;
}

}  // namespace vocal
