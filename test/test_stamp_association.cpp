#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "test_support.h"
#include "vocal/core/stamp_association.h"
#include "vocal/core/tum_sequence.h"

namespace {
// TUM's associate.py, written as directly as possible: all pairs, sorted by difference, greedy.
std::vector<std::pair<std::size_t, std::size_t>> referenceAssociate(const std::vector<double>& a,
                                                                    const std::vector<double>& b, double max_difference) {
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j)
      if (std::abs(a[i] - b[j]) < max_difference) candidates.emplace_back(std::abs(a[i] - b[j]), i, j);
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> used_a(a.size()), used_b(b.size());
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  for (const auto& [d, i, j] : candidates) {
    if (!used_a[i] && !used_b[j]) {
      used_a[i] = used_b[j] = true;
      matches.emplace_back(i, j);
    }
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

void expectSame(const std::vector<vocal::StampMatch>& got,
                const std::vector<std::pair<std::size_t, std::size_t>>& expected) {
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].first, expected[k].first);
    EXPECT_EQ(got[k].second, expected[k].second);
  }
}
}  // namespace

TEST(StampAssociation, GreedyClosestFirstNotNearestNeighbour) {
  // Nearest neighbour would give both first stamps the second stamp 1.012; the TUM rule gives it to
  // 1.010 (closer) and leaves 1.000 with 0.995.
  const std::vector<double> first = {1.000, 1.010};
  const std::vector<double> second = {0.995, 1.012};
  const auto matches = vocal::associateStamps(first, second, 0.02);
  ASSERT_EQ(matches.size(), 2u);
  EXPECT_EQ(matches[0].first, 0u);
  EXPECT_EQ(matches[0].second, 0u);
  EXPECT_EQ(matches[1].first, 1u);
  EXPECT_EQ(matches[1].second, 1u);
  EXPECT_TRUE(vocal::associateStamps({1.0}, {1.05}, 0.02).empty());
}

TEST(StampAssociation, MatchesTheReferenceRuleOnRandomStreams) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.012, 0.012);
  std::bernoulli_distribution drop(0.1);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> a, b;
    for (int i = 0; i < 300; ++i) {
      if (!drop(rng)) a.push_back(i / 30.0 + jitter(rng) * 0.2);
      if (!drop(rng)) b.push_back(i / 30.0 + jitter(rng));
    }
    std::sort(b.begin(), b.end());
    expectSame(vocal::associateStamps(a, b, 0.02), referenceAssociate(a, b, 0.02));
  }
}

TEST(StampAssociation, MatchesTheTumRuleOnRealData) {
  const std::string folder = vocal_test::tumDataFolder();
  if (folder.empty()) GTEST_SKIP() << "TUM data not present";
  std::vector<double> rgb, depth;
  for (const auto& e : vocal::readTumImageList(folder + "/rgb.txt", folder)) rgb.push_back(e.stamp);
  for (const auto& e : vocal::readTumImageList(folder + "/depth.txt", folder)) depth.push_back(e.stamp);
  const auto expected = referenceAssociate(rgb, depth, 0.02);
  expectSame(vocal::associateStamps(rgb, depth, 0.02), expected);
  // The sequence uses the same rule.
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder);
  ASSERT_EQ(sequence.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(sequence.entry(k).rgb.stamp, rgb[expected[k].first]);
    EXPECT_EQ(sequence.entry(k).depth.stamp, depth[expected[k].second]);
  }
}

TEST(StampAssociation, ClosestIndex) {
  const std::vector<double> stamps = {1.0, 2.0, 3.0};
  EXPECT_EQ(vocal::closestStampIndex(stamps, -5.0), 0u);
  EXPECT_EQ(vocal::closestStampIndex(stamps, 1.4), 0u);
  EXPECT_EQ(vocal::closestStampIndex(stamps, 1.6), 1u);
  EXPECT_EQ(vocal::closestStampIndex(stamps, 9.0), 2u);
}
