#include "scanbus/foxglove_bridge/channels.hpp"

#include <gtest/gtest.h>

using namespace scanbus::foxglove_bridge;

TEST(Channels, ATopicIsOfferedOnceAndComesBackUnderANewId) {
  Channels channels;
  const auto scan = channels.offer("/scan", "sensor_msgs/msg/LaserScan", "schema");
  ASSERT_TRUE(scan);
  EXPECT_FALSE(channels.offer("/scan", "sensor_msgs/msg/LaserScan", "schema"));
  EXPECT_EQ(channels.withdraw("/scan"), scan->id);
  EXPECT_FALSE(channels.withdraw("/scan"));
  const auto again = channels.offer("/scan", "sensor_msgs/msg/LaserScan", "schema");
  ASSERT_TRUE(again);
  EXPECT_NE(again->id, scan->id);
  EXPECT_EQ(channels.offered().size(), 1u);
}

TEST(Channels, SubscribersAndTheTopicsReadersAreNeededFor) {
  Channels channels;
  const uint32_t scan = channels.offer("/scan", "t", "s")->id;
  const uint32_t cloud = channels.offer("/cloud/assembled", "t", "s")->id;
  channels.add_client(1);
  channels.add_client(2);
  EXPECT_EQ(channels.clients(), (std::vector<ClientId>{1, 2}));
  EXPECT_TRUE(channels.wanted_topics().empty());
  EXPECT_EQ(channels.subscribe(1, {7, scan}), "");
  EXPECT_EQ(channels.subscribe(2, {0, scan}), "");
  EXPECT_EQ(channels.subscribe(2, {1, cloud}), "");
  EXPECT_EQ(channels.subscribers(scan), (std::vector<std::pair<ClientId, uint32_t>>{{1, 7}, {2, 0}}));
  EXPECT_EQ(channels.wanted_topics(), (std::set<std::string>{"/scan", "/cloud/assembled"}));
  channels.remove_client(2);  // a client that leaves takes its subscriptions along
  EXPECT_EQ(channels.wanted_topics(), std::set<std::string>{"/scan"});
  EXPECT_EQ(channels.unsubscribe(1, 7), "");
  EXPECT_TRUE(channels.wanted_topics().empty());
}

TEST(Channels, RefusedSubscriptionsSayWhy) {
  Channels channels;
  const uint32_t scan = channels.offer("/scan", "t", "s")->id;
  channels.add_client(1);
  EXPECT_EQ(channels.subscribe(1, {3, 99}), "subscription 3: no channel 99 is advertised");
  EXPECT_EQ(channels.subscribe(1, {3, scan}), "");
  EXPECT_EQ(channels.subscribe(1, {3, scan}), "subscription 3 is already in use");
  EXPECT_EQ(channels.unsubscribe(1, 4), "no subscription 4 to end");
}

TEST(Channels, AWithdrawnTopicEndsItsSubscriptions) {
  Channels channels;
  const uint32_t scan = channels.offer("/scan", "t", "s")->id;
  channels.add_client(1);
  ASSERT_EQ(channels.subscribe(1, {3, scan}), "");
  channels.withdraw("/scan");
  EXPECT_TRUE(channels.subscribers(scan).empty());
  EXPECT_TRUE(channels.wanted_topics().empty());
  EXPECT_EQ(channels.unsubscribe(1, 3), "no subscription 3 to end");
}
