#include "rangekit/record/merge.hpp"

#include <gtest/gtest.h>

#include "rangekit/ls5/family.hpp"
#include "record/fake_source.hpp"

namespace rangekit::record {
namespace {

using namespace testing;

std::vector<Sample> drain(SampleSource& source) {
  std::vector<Sample> samples;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (!source.finished() && std::chrono::steady_clock::now() < deadline) {
    if (auto item = source.next(100ms)) samples.push_back(std::get<Sample>(*item));
  }
  return samples;
}

TEST(Merge, EveryItemOfEverySourceKeepingEachSourcesOrder) {
  std::vector<StreamItem> uls_items;
  std::vector<StreamItem> ls5_items;
  for (int i = 0; i < 50; ++i) {
    uls_items.emplace_back(uls_averaging(std::chrono::milliseconds(i)));
    auto ls5 = ls5_result(static_cast<std::uint16_t>(i), i * 1.0, ls5::SignalState::ok);
    ls5_items.emplace_back(ls5);
  }
  std::vector<SampleSourcePtr> sources;
  sources.push_back(std::make_unique<FakeSource>(uls_items));
  sources.push_back(std::make_unique<FakeSource>(ls5_items));
  auto merged = merge_sources(std::move(sources));
  const auto samples = drain(*merged);
  ASSERT_TRUE(merged->finished());
  ASSERT_EQ(samples.size(), 100u);
  int next_uls = 0;
  int next_ls5 = 0;
  for (const auto& sample : samples) {
    if (sample.device == "uls") {
      EXPECT_EQ(sample.time, at(std::chrono::milliseconds(next_uls++)));
    } else {
      EXPECT_EQ(sample.get(ls5::channel::code), next_ls5++);
    }
  }
  EXPECT_EQ(next_uls, 50);
  EXPECT_EQ(next_ls5, 50);
}

TEST(Merge, StopStopsEverySource) {
  auto first = std::make_unique<FakeSource>(std::vector<StreamItem>{}, true);
  auto second = std::make_unique<FakeSource>(std::vector<StreamItem>{}, true);
  auto* first_view = first.get();
  auto* second_view = second.get();
  std::vector<SampleSourcePtr> sources;
  sources.push_back(std::move(first));
  sources.push_back(std::move(second));
  auto merged = merge_sources(std::move(sources));
  EXPECT_FALSE(merged->finished());
  merged->stop();
  EXPECT_TRUE(first_view->stopped());
  EXPECT_TRUE(second_view->stopped());
  drain(*merged);
  EXPECT_TRUE(merged->finished());
}

TEST(Merge, NoSourcesIsFinishedAtOnce) {
  auto merged = merge_sources({});
  EXPECT_TRUE(merged->finished());
  EXPECT_FALSE(merged->next(10ms).has_value());
}

}  // namespace
}  // namespace rangekit::record
