// Every input in test/fuzz/corpus (the fuzzers' seeds and every crash they found, kept after the fix)
// through the same target functions scripts/fuzz fuzzes: each is taken or refused with InputError,
// nothing else escapes. Built with the project's compiler, so a crash here is a crash on a robot.

#include <dirent.h>

#include <fstream>
#include <iterator>
#include <set>

#include <gtest/gtest.h>

#include "fuzz/fuzz_targets.h"

namespace {
const std::string kCorpus = std::string(VOCAL_SOURCE_DIR) + "/test/fuzz/corpus";

std::vector<std::string> entriesOf(const std::string& folder) {
  std::vector<std::string> names;
  if (DIR* dir = opendir(folder.c_str())) {
    while (const dirent* entry = readdir(dir))
      if (entry->d_name[0] != '.') names.push_back(entry->d_name);
    closedir(dir);
  }
  return names;
}
}  // namespace

TEST(FuzzCorpus, EveryTargetHasACorpusAndEveryCorpusATarget) {
  std::set<std::string> targets;
  for (const vocal_fuzz::FuzzTarget& target : vocal_fuzz::fuzzTargets()) {
    targets.insert(target.name);
    EXPECT_FALSE(entriesOf(kCorpus + "/" + target.name).empty()) << "no seed for fuzz target " << target.name;
  }
  for (const std::string& folder : entriesOf(kCorpus)) EXPECT_TRUE(targets.count(folder)) << "corpus of no target: " << folder;
}

TEST(FuzzCorpus, EveryInputIsTakenOrRefusedWithItsProblemNamed) {
  int inputs = 0;
  for (const vocal_fuzz::FuzzTarget& target : vocal_fuzz::fuzzTargets()) {
    for (const std::string& name : entriesOf(kCorpus + "/" + target.name)) {
      std::ifstream file(kCorpus + "/" + target.name + "/" + name, std::ios::binary);
      const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
      EXPECT_NO_THROW(target.run(bytes.data(), bytes.size())) << target.name << "/" << name;
      ++inputs;
    }
  }
  EXPECT_GT(inputs, 0);
}
