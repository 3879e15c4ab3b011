// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1, as Foxglove's
// ws-protocol publishes it), server side, without a socket: the JSON messages the server
// sends, the binary frames that carry samples and time, and the client's requests parsed.
// Only what a bridge of DDS topics needs: channels, subscriptions and time; the optional
// parts (client publishing, parameters, services, assets) are not offered.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace scanbus::foxglove_bridge {

inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";

// One topic offered to clients: its samples are CDR (with the 4-byte encapsulation header,
// as DDS carries them), described by a ROS 2 .msg schema (schema encoding ros2msg).
struct Channel {
  uint32_t id = 0;
  std::string topic;        // the ROS name, "/scan"
  std::string schema_name;  // "sensor_msgs/msg/LaserScan"
  std::string schema;       // .msg text, dependencies after it (the recorder's schemas)
};

enum class StatusLevel { Info = 0, Warning = 1, Error = 2 };

// Server messages (JSON text frames).
std::string server_info(const std::string& name, const std::vector<std::string>& capabilities,
                        const std::string& session_id);
std::string advertise(const std::vector<Channel>& channels);
std::string unadvertise(const std::vector<uint32_t>& channel_ids);
std::string status(StatusLevel level, const std::string& message);

// Binary frames: a sample is this header (op 0x01, the client's subscription id, the receive
// time in ns since the epoch, both little-endian) followed by its bytes, so one sample's
// bytes serve every client. Time (op 0x02) is whole.
constexpr size_t kMessageDataHeaderSize = 13;
std::array<uint8_t, kMessageDataHeaderSize> message_data_header(uint32_t subscription_id, uint64_t receive_time_ns);
std::array<uint8_t, 9> time_frame(uint64_t time_ns);

struct Subscription {
  uint32_t id = 0;  // chosen by the client, unique among its subscriptions
  uint32_t channel_id = 0;
};

struct ClientRequest {
  enum class Op { Subscribe, Unsubscribe } op = Op::Subscribe;
  std::vector<Subscription> subscriptions;  // Subscribe
  std::vector<uint32_t> subscription_ids;   // Unsubscribe
};

class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A client's text frame; throws ProtocolError naming what is wrong (not JSON, an op this
// server does not offer, a missing or mistyped field), which the server sends back as status.
ClientRequest parse_client_request(const std::string& text);

}  // namespace scanbus::foxglove_bridge
