#include "link/Link.h"

#include <gtest/gtest.h>

namespace ambler::link {
namespace {

TEST(LinkHealth, StaleWithoutDataAndAfterTheTimeout) {
  LinkHealth health(3.0);
  EXPECT_TRUE(health.stale(0.0));
  EXPECT_FALSE(health.ageS(0.0).has_value());
  health.heard(10.0);
  EXPECT_FALSE(health.stale(12.9));
  EXPECT_DOUBLE_EQ(*health.ageS(12.5), 2.5);
  EXPECT_TRUE(health.stale(13.1));
}

// Answers one message on the second call, nothing otherwise.
class OneMessageLink : public Link {
 public:
  void send(const Command&) override {}
  std::vector<Telemetry> receive(std::chrono::milliseconds) override {
    if (++calls_ != 2) return {};
    return {Telemetry{1, 0.0, Heartbeat{1, false, {}, {}, {}}}};
  }
  std::string describe() const override { return "one message"; }

 private:
  int calls_ = 0;
};

TEST(WatchedLink, NotesWhenTheRoverLastSpoke) {
  OneMessageLink inner;
  LinkHealth health(3.0);
  double now = 100.0;
  WatchedLink link(inner, health, [&] { return now; });
  EXPECT_TRUE(link.receive(std::chrono::milliseconds(0)).empty());
  EXPECT_FALSE(health.ageS(now).has_value());  // nothing heard yet
  now = 101.0;
  EXPECT_EQ(link.receive(std::chrono::milliseconds(0)).size(), 1u);
  now = 105.0;
  EXPECT_TRUE(link.receive(std::chrono::milliseconds(0)).empty());
  EXPECT_DOUBLE_EQ(*health.ageS(now), 4.0);  // silence does not count as hearing
  EXPECT_TRUE(health.stale(now));
  EXPECT_EQ(link.describe(), "one message");
}

TEST(WatchedLink, ShowsItsObserverWhatPassesBothWays) {
  OneMessageLink inner;
  LinkHealth health(3.0);
  std::vector<std::string> seen;
  WatchedLink link(inner, health, [] { return 0.0; },
                   {[&](const Command& c) { seen.push_back("sent " + typeName(c.body)); },
                    [&](const Telemetry& t) { seen.push_back("received " + typeName(t.body)); }});
  link.send(
      Command{.rover_id = 1, .operator_id = "alice", .sequence = 1, .body = Hold{}, .hmac = {}});
  link.receive(std::chrono::milliseconds(0));
  link.receive(std::chrono::milliseconds(0));
  EXPECT_EQ(seen, (std::vector<std::string>{"sent Hold", "received Heartbeat"}));
}

}  // namespace
}  // namespace ambler::link
