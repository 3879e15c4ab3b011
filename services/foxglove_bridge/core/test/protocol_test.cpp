#include "scanbus/foxglove_bridge/protocol.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace scanbus::foxglove_bridge;
using nlohmann::json;

TEST(FoxgloveProtocol, AdvertisedChannelsAreCdrWithRos2MsgSchemas) {
  const json message = json::parse(advertise({{3, "/scan", "sensor_msgs/msg/LaserScan", "float32 angle_min\n"}}));
  EXPECT_EQ(message["op"], "advertise");
  ASSERT_EQ(message["channels"].size(), 1u);
  const auto& channel = message["channels"][0];
  EXPECT_EQ(channel["id"], 3);
  EXPECT_EQ(channel["topic"], "/scan");
  EXPECT_EQ(channel["encoding"], "cdr");
  EXPECT_EQ(channel["schemaName"], "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(channel["schemaEncoding"], "ros2msg");
  EXPECT_EQ(channel["schema"], "float32 angle_min\n");
  EXPECT_EQ(json::parse(unadvertise({3, 4}))["channelIds"], json::array({3, 4}));
}

TEST(FoxgloveProtocol, ServerInfoNamesItsCapabilities) {
  const json info = json::parse(server_info("scanbus", {"time"}, "42"));
  EXPECT_EQ(info["op"], "serverInfo");
  EXPECT_EQ(info["capabilities"], json::array({"time"}));
  EXPECT_EQ(info["sessionId"], "42");
}

TEST(FoxgloveProtocol, BinaryFramesAreLittleEndian) {
  const auto header = message_data_header(0x01020304, 0x1122334455667788ull);
  const std::array<uint8_t, 13> expected{0x01, 0x04, 0x03, 0x02, 0x01, 0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11};
  EXPECT_EQ(header, expected);
  const auto time = time_frame(1);
  EXPECT_EQ(time[0], 0x02);
  EXPECT_EQ(time[1], 1);
  EXPECT_EQ(time[8], 0);
}

TEST(FoxgloveProtocol, SubscribeAndUnsubscribeAreParsed) {
  const auto subscribe =
      parse_client_request(R"({"op":"subscribe","subscriptions":[{"id":7,"channelId":2},{"id":8,"channelId":5}]})");
  EXPECT_EQ(subscribe.op, ClientRequest::Op::Subscribe);
  ASSERT_EQ(subscribe.subscriptions.size(), 2u);
  EXPECT_EQ(subscribe.subscriptions[1].id, 8u);
  EXPECT_EQ(subscribe.subscriptions[1].channel_id, 5u);
  const auto unsubscribe = parse_client_request(R"({"op":"unsubscribe","subscriptionIds":[7]})");
  EXPECT_EQ(unsubscribe.op, ClientRequest::Op::Unsubscribe);
  EXPECT_EQ(unsubscribe.subscription_ids, std::vector<uint32_t>{7});
}

TEST(FoxgloveProtocol, BadRequestsAreNamed) {
  const auto error_of = [](const std::string& text) {
    try {
      parse_client_request(text);
    } catch (const ProtocolError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error_of("not json"), "a text message must be a JSON object");
  EXPECT_EQ(error_of(R"({"subscriptions":[]})"), "a message needs an 'op' string");
  EXPECT_EQ(error_of(R"({"op":"getParameters","parameterNames":[]})"),
            "op 'getParameters' is not offered by this server (subscribe, unsubscribe)");
  EXPECT_EQ(error_of(R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":2}]})"),
            "'id' must be an unsigned 32-bit integer");
  EXPECT_EQ(error_of(R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":2}]})"),
            "'id' must be an unsigned 32-bit integer");
  EXPECT_EQ(error_of(R"({"op":"unsubscribe"})"), "'subscriptionIds' must be an array");
}

TEST(FoxgloveProtocol, AStatusWithInvalidUtf8IsStillJson) {
  const json message = json::parse(status(StatusLevel::Warning, "topic \xff"));
  EXPECT_EQ(message["level"], 1);
  EXPECT_EQ(message["op"], "status");
}
