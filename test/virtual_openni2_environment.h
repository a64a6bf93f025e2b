#pragma once
// Makes OpenNI2 load the virtual device of test/virtual_openni2_device.cpp. OpenNI2 looks for drivers
// beside the libOpenNI2.so.0 the process loaded, so the test program re-executes itself once with the
// folder holding a copy of it (and the virtual driver) first on LD_LIBRARY_PATH. The system's OpenNI2
// setup is not touched.

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace vocal_test {

// Returns in the re-executed process; in the first one it does not return (or exits on failure).
inline void reexecWithVirtualOpenni2(char** argv) {
  if (std::getenv("VOCAL_OPENNI2_TEST_REEXEC")) return;
  const char* old_path = std::getenv("LD_LIBRARY_PATH");
  const std::string path = std::string(VOCAL_OPENNI2_TEST_DIR) + (old_path ? std::string(":") + old_path : "");
  ::setenv("LD_LIBRARY_PATH", path.c_str(), 1);
  ::setenv("VOCAL_OPENNI2_TEST_REEXEC", "1", 1);
  ::execv("/proc/self/exe", argv);
  std::perror("re-exec with the virtual OpenNI2 device");
  std::exit(1);
}

}  // namespace vocal_test
