// What one client may not exhaust through captures (docs/api.md, "Captures"): the number
// running at once, and the disk a start needs free. Each refusal is Errc::limit, which the
// HTTP face answers 409, with a message that says what to do.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "hub/site_fixture.hpp"
#include "rangekit/hub/captures.hpp"
#include "rangekit/hub/hub.hpp"

namespace capture_limits_test {

using namespace rangekit;

bool mentions(const Error& error, const std::string& text) { return error.message.find(text) != std::string::npos; }

TEST(CaptureLimits, NoMoreRunAtOnceThanTheLimitAndAStoppedOneFreesItsPlace) {
  hub_test::Site site;
  auto hub = hub::Hub::start(site.config);
  hub::CaptureLimits limits;
  limits.running = 2;
  limits.min_free_bytes = 0;
  hub::CaptureManager captures(*hub, (site.temp.path / "captures").string(), limits);
  auto first = captures.start({});
  auto second = captures.start({"silo"});
  ASSERT_TRUE(first.ok() && second.ok());
  auto third = captures.start({});
  ASSERT_FALSE(third.ok());
  EXPECT_EQ(third.error().code, Errc::limit);
  EXPECT_TRUE(mentions(third.error(), "2 captures are running")) << third.error().message;
  EXPECT_TRUE(mentions(third.error(), "stop one first")) << third.error().message;
  EXPECT_EQ(captures.list().size(), 2u) << "a refused start leaves no capture behind";

  ASSERT_TRUE(captures.stop(first->id).ok());
  auto again = captures.start({});
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(captures.list().size(), 3u);
}

TEST(CaptureLimits, AStartNeedsFreeSpaceAndTheRefusalSaysHowMuch) {
  hub_test::Site site;
  auto hub = hub::Hub::start(site.config);
  hub::CaptureLimits limits;
  limits.min_free_bytes = std::numeric_limits<std::uintmax_t>::max();  // more than any disk has
  const std::string folder = (site.temp.path / "captures").string();
  hub::CaptureManager captures(*hub, folder, limits);
  auto refused = captures.start({});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, Errc::limit);
  EXPECT_TRUE(mentions(refused.error(), folder)) << refused.error().message;
  EXPECT_TRUE(mentions(refused.error(), "MiB free")) << refused.error().message;
  EXPECT_TRUE(captures.list().empty());
}

}  // namespace capture_limits_test
