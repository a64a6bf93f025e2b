// libFuzzer entry for one target, chosen at compile time (VOCAL_FUZZ_TARGET): scripts/fuzz builds one
// binary per target with clang's -fsanitize=fuzzer,address,undefined.
#include <cstdio>
#include <cstdlib>

#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const vocal_fuzz::FuzzTarget* target = [] {
    const vocal_fuzz::FuzzTarget* found = vocal_fuzz::findFuzzTarget(VOCAL_FUZZ_TARGET);
    if (!found) {
      std::fprintf(stderr, "fuzz_main: no fuzz target named '%s'\n", VOCAL_FUZZ_TARGET);
      std::abort();
    }
    return found;
  }();
  target->run(data, size);
  return 0;
}
