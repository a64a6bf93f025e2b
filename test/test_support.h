#pragma once
// Helpers shared by the tests: temporary folders and small synthetic sequences.

#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "vocal/core/errors.h"
#include "vocal/simulation/synthetic_sequence.h"

namespace vocal_test {

// The folders makeTempFolder made, removed when the test program exits (bags and clouds of a whole run
// filled a developer's disk); kept when VOCAL_KEEP_TEST_FILES is set, or when the program crashes.
inline std::vector<std::string>& tempFolders() {
  static std::vector<std::string> folders;
  return folders;
}
inline void removeTempFolders() {
  if (std::getenv("VOCAL_KEEP_TEST_FILES")) return;
  for (const std::string& folder : tempFolders()) {
    const std::string command = "rm -rf '" + folder + "'";
    if (std::system(command.c_str()) != 0) std::fprintf(stderr, "could not remove %s\n", folder.c_str());
  }
}

// A fresh empty folder under the test temp dir.
inline std::string makeTempFolder(const std::string& name) {
  const std::string path = ::testing::TempDir() + "/vocal_" + name + "_" + std::to_string(::getpid());
  const std::string command = "rm -rf '" + path + "' && mkdir -p '" + path + "'";
  if (std::system(command.c_str()) != 0) {
    ADD_FAILURE() << "cannot create " << path;
  }
  if (tempFolders().empty()) std::atexit(removeTempFolders);
  tempFolders().push_back(path);
  return path;
}

// The message of the InputError `f` throws, or "(no error)".
inline std::string inputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const vocal::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// Checks `done` under `mutex` every 50 ms until it holds or `seconds` pass; whether it held.
inline bool waitUntil(std::mutex& mutex, double seconds, const std::function<bool()>& done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (done()) return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::lock_guard<std::mutex> lock(mutex);
  return done();
}

inline void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
inline std::string readText(const std::string& path) {
  std::ifstream file(path);
  return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

inline vocal::SyntheticSequenceOptions smallSequenceOptions(int frames = 8) {
  vocal::SyntheticSequenceOptions options;
  options.width = 160;
  options.height = 120;
  options.trajectory.frames = frames;
  return options;
}

// Path of the real TUM data beside the repository, or "" (with a loud note) when it is not there.
inline std::string tumDataFolder() {
  const std::string folder = std::string(VOCAL_TUM_DATA_DIR) + "/rgbd_dataset_freiburg1_xyz_first300";
  std::ifstream probe(folder + "/rgb.txt");
  if (!probe) {
    std::cerr << "\n*** TUM data not found at " << folder << ": real-data checks are SKIPPED ***\n\n";
    return "";
  }
  return folder;
}

#ifdef VOCAL_TOOLS_DIR
// A command's exit code and what it printed (stdout and stderr together). runTool runs one of the
// installed command-line tools as a user runs it.
struct RunResult {
  int exit_code = -1;
  std::string output;
};

// A shell command's exit code and output (stdout and stderr together).
inline RunResult runCommand(const std::string& command_line) {
  const std::string command = command_line + " 2>&1";
  RunResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0;) result.output.append(buffer, n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

inline RunResult runTool(const std::string& arguments) { return runCommand(std::string(VOCAL_TOOLS_DIR) + "/" + arguments); }
#endif

// Path of a real calibration recording beside the repository (../shared/data/real_rigs/NAME), or ""
// (with a loud note) when it is not there.
// `probe_file`: a file the recording's folder holds.
inline std::string realRigFolder(const std::string& name, const std::string& probe_file = "camera_info.yaml") {
  const std::string folder = std::string(VOCAL_REAL_RIGS_DIR) + "/" + name;
  std::ifstream probe(folder + "/" + probe_file);
  if (!probe) {
    std::cerr << "\n*** real rig recording not found at " << folder << ": real-data checks are SKIPPED ***\n\n";
    return "";
  }
  return folder;
}

}  // namespace vocal_test
