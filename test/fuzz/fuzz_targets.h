#pragma once
// The inputs vocal takes from outside (config files, text files, ROS messages), each as one function
// of raw bytes: the libFuzzer harnesses (scripts/fuzz) and the corpus replay (test_fuzz_corpus) call
// the same functions. A function returns when the input was taken or refused with InputError; any
// other exception escapes, and a crash or sanitizer report ends the process: both are findings.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vocal_fuzz {

struct FuzzTarget {
  const char* name;         // also the corpus folder's name: test/fuzz/corpus/<name>/
  const char* description;  // what it feeds, for the table the fuzz script prints
  void (*run)(const std::uint8_t* data, std::size_t size);
};

const std::vector<FuzzTarget>& fuzzTargets();

// nullptr when no target has that name.
const FuzzTarget* findFuzzTarget(const std::string& name);

}  // namespace vocal_fuzz
