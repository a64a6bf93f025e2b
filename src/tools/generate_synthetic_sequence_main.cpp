// generate_synthetic_sequence OUTPUT_FOLDER [options]: renders a synthetic RGB-D sequence with ground
// truth into the TUM layout.

#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "vocal/core/errors.h"
#include "vocal/simulation/blank_wall_visit.h"
#include "vocal/simulation/synthetic_sequence.h"
#include "vocal/tools/command_line.h"

namespace {
const char kUsage[] =
    "usage: generate_synthetic_sequence OUTPUT_FOLDER [options]\n"
    "  --scene room|wall|bare_room|blank_wall  indoor room (default), one flat textured wall, untextured\n"
    "                               room, the room with a blank panel beside the path\n"
    "  --blank-wall-visit SECONDS   scene blank_wall, the path leaving the room for SECONDS facing the\n"
    "                               blank panel, then back (4 s room before, 1 s turn each way, 2 s room after;\n"
    "                               --frames ignored)\n"
    "  --frames N                   number of frames (default 300)\n"
    "  --width W --height H         image size (default 640x480; intrinsics scale with it)\n"
    "  --rate HZ                    frame rate (default 30)\n"
    "  --speed M_PER_S              mean camera speed (default 0.25)\n"
    "  --seed S                     motion and noise seed (default 1)\n"
    "  --trajectory FILE            render along this TUM trajectory instead of a generated one\n"
    "  --kinect-noise               Kinect-like sensor: colour noise (2 levels); depth noise growing\n"
    "                               with z^2, disparity quantisation,\n"
    "                               drop-outs at depth edges and --missing of the pixels\n"
    "  --axial-noise, --quantize    only the noise, or only the quantisation, of --kinect-noise\n"
    "  --missing F                  fraction of randomly missing depth pixels (default 0.02 with\n"
    "                               --kinect-noise, else 0)\n"
    "  --cover FIRST:COUNT          a hand over the lens (no depth, dark colour) for COUNT frames from\n"
    "                               frame FIRST (counted from 0)\n"
    "  --rolling-shutter S          rows read one after another over S seconds, as a Kinect's are\n"
    "                               (0.02 matches the odometry's default; default 0: a global shutter)\n"
    "  --exposure S                 each row exposed over S seconds: colour blurred along the motion,\n"
    "                               depth lost where it smears (default 0: sharp)\n"
    "  --quiet                      no progress line\n";

int run(const vocal::CommandLine& args) {
  vocal::SyntheticSequenceOptions options;
  options.scene = vocal::parseSceneVariant(args.text("scene", "room"));
  options.width = args.integer("width", 640);
  options.height = args.integer("height", 480);
  options.trajectory.frames = args.integer("frames", 300);
  options.trajectory.frame_rate = args.number("rate", 30.0);
  options.trajectory.speed = args.number("speed", 0.25);
  options.trajectory.seed = static_cast<std::uint32_t>(args.integer("seed", 1));
  options.trajectory_path = args.text("trajectory", "");
  if (args.has("blank-wall-visit")) {
    if (!options.trajectory_path.empty()) throw vocal::InputError("--blank-wall-visit and --trajectory exclude each other");
    options.scene = vocal::SceneVariant::kBlankWall;
    vocal::BlankWallVisitOptions visit;
    visit.frame_rate = options.trajectory.frame_rate;
    visit.wall_seconds = args.number("blank-wall-visit", visit.wall_seconds);
    options.poses = vocal::generateBlankWallVisit(visit);
  }
  if (args.has("kinect-noise")) {
    options.sensor_model = vocal::kinectLikeSensorModel(args.number("missing", 0.02));
  } else {
    options.sensor_model.missing_fraction = args.number("missing", 0.0);
    options.sensor_model.axial_noise = args.has("axial-noise");
    options.sensor_model.quantize_disparity = args.has("quantize");
  }
  options.rolling_shutter_readout = args.number("rolling-shutter", 0.0);
  options.exposure = args.number("exposure", 0.0);
  if (args.has("cover")) {
    const std::string cover = args.text("cover", "");
    const std::size_t colon = cover.find(':');
    try {
      if (colon == std::string::npos) throw std::invalid_argument("no colon");
      options.covered_from = std::stoi(cover.substr(0, colon));
      options.covered_frames = std::stoi(cover.substr(colon + 1));
    } catch (const std::exception&) {
      throw vocal::InputError("--cover '" + cover + "' is not FIRST:COUNT (e.g. 40:10)");
    }
  }
  const bool quiet = args.has("quiet");
  const std::string folder = args.positional()[0];
  const vocal::SyntheticSequence sequence =
      vocal::writeSyntheticSequence(folder, options, [quiet](int done, int total) {
        if (!quiet) std::fprintf(stderr, "\rrendering frame %d/%d", done, total);
      });
  if (!quiet) std::fprintf(stderr, "\n");
  std::cout << "wrote " << sequence.ground_truth.size() << " frames (" << sequence.camera.width << "x"
            << sequence.camera.height << ", scene " << vocal::sceneVariantName(options.scene) << ") to " << folder
            << "\n";
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("generate_synthetic_sequence", kUsage, run, argc, argv,
                        {"scene", "frames", "width", "height", "rate", "speed", "seed", "trajectory", "missing", "cover",
                         "rolling-shutter", "blank-wall-visit", "exposure"},
                        {"kinect-noise", "axial-noise", "quantize", "quiet"}, 1);
}
