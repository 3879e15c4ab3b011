#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <type_traits>

#include "scanbus/topics.hpp"
#include "scanbus/typed_topics.hpp"

using namespace scanbus;

TEST(Topics, EveryTopicCarriesTheRos2Prefix) {
  for (const auto& topic : topic_catalogue()) EXPECT_EQ(topic.name.rfind("rt/", 0), 0u) << topic.name;
}

TEST(Topics, EveryTypeUsesRos2DdsNaming) {
  for (const auto& topic : topic_catalogue()) {
    EXPECT_NE(topic.type.find("::msg::dds_::"), std::string::npos) << topic.type;
    EXPECT_EQ(topic.type.back(), '_') << topic.type;
  }
}

TEST(Topics, NamesAreUnique) {
  for (const auto& topic : topic_catalogue()) EXPECT_EQ(find_topic(topic.name), &topic);
}

TEST(Topics, UnknownTopicIsNamed) {
  EXPECT_EQ(find_topic("rt/nope"), nullptr);
  EXPECT_THROW(topic_info("rt/nope"), std::invalid_argument);
}

TEST(Topics, QosOverridesFromConfig) {
  const Config config =
      Config::parse("qos:\n  rt/scanner/cloud: {reliability: best_effort, durability: volatile, depth: 3}\n", "q.yaml");
  const QosSettings qos = qos_from_config(config.section("qos"), topic_info("rt/scanner/cloud"));
  EXPECT_FALSE(qos.reliable);
  EXPECT_FALSE(qos.transient_local);
  EXPECT_EQ(qos.depth, 3);
  EXPECT_NO_THROW(config.check_all_read());
}

TEST(Topics, BadQosValueIsAConfigError) {
  const Config config = Config::parse("qos:\n  rt/scan: {reliability: sometimes}\n", "q.yaml");
  EXPECT_THROW(qos_from_config(config.section("qos"), topic_info("rt/scan")), ConfigError);
}

// docs/topics.md is the user's view of the catalogue: it must list every topic with its
// type, QoS, publishers and subscribers as the code has them (the last two grant DDS
// Security permissions: scanbus security permissions).
TEST(Topics, DocumentationListsEveryTopic) {
  std::ifstream in(std::string(SCANBUS_SOURCE_DIR) + "/docs/topics.md");
  ASSERT_TRUE(in) << "docs/topics.md missing";
  std::stringstream text;
  text << in.rdbuf();
  for (const auto& topic : topic_catalogue()) {
    const std::string row = "| `" + topic.name + "` | `" + topic.type + "` | " + describe(topic.qos) + " | " +
                            topic.publishers + " | " + topic.subscribers + " |";
    EXPECT_NE(text.str().find(row), std::string::npos) << "docs/topics.md lacks the row starting: " << row;
  }
}

TEST(TypedTopics, MatchTheCatalogue) {
  size_t count = 0;
  std::set<std::string> names;
  scanbus::topics::for_each_typed_topic([&](const auto& topic) {
    using Type = typename std::decay_t<decltype(topic)>::Type;
    const scanbus::TopicInfo* info = scanbus::find_topic(topic.name);
    ASSERT_NE(info, nullptr) << topic.name << " is not in the catalogue";
    EXPECT_EQ(info->type, Type().getName()) << topic.name;
    names.insert(topic.name);
    ++count;
  });
  EXPECT_EQ(names.size(), count) << "a topic named twice";
  EXPECT_EQ(count, scanbus::topic_catalogue().size()) << "a catalogue topic without its typed descriptor";
}
