#include "scanbus/foxglove_bridge/protocol.hpp"

#include <nlohmann/json.hpp>

namespace scanbus::foxglove_bridge {

namespace {

using nlohmann::json;

template <size_t N>
void put_le(std::array<uint8_t, N>& out, size_t at, uint64_t value, size_t bytes) {
  for (size_t i = 0; i < bytes; ++i) out[at + i] = static_cast<uint8_t>(value >> (8 * i));
}

uint32_t id_field(const json& object, const char* key) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number_unsigned() || it->get<uint64_t>() > UINT32_MAX)
    throw ProtocolError(std::string("'") + key + "' must be an unsigned 32-bit integer");
  return it->get<uint32_t>();
}

const json& array_field(const json& object, const char* key) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_array()) throw ProtocolError(std::string("'") + key + "' must be an array");
  return *it;
}

}  // namespace

std::string server_info(const std::string& name, const std::vector<std::string>& capabilities,
                        const std::string& session_id) {
  return json{{"op", "serverInfo"},           {"name", name},
              {"capabilities", capabilities}, {"supportedEncodings", json::array()},
              {"metadata", json::object()},   {"sessionId", session_id}}
      .dump();
}

std::string advertise(const std::vector<Channel>& channels) {
  json list = json::array();
  for (const auto& channel : channels)
    list.push_back({{"id", channel.id},
                    {"topic", channel.topic},
                    {"encoding", "cdr"},
                    {"schemaName", channel.schema_name},
                    {"schema", channel.schema},
                    {"schemaEncoding", "ros2msg"}});
  return json{{"op", "advertise"}, {"channels", list}}.dump();
}

std::string unadvertise(const std::vector<uint32_t>& channel_ids) {
  return json{{"op", "unadvertise"}, {"channelIds", channel_ids}}.dump();
}

std::string status(StatusLevel level, const std::string& message) {
  // Invalid UTF-8 (a topic name from the wire) is replaced rather than thrown on.
  return json{{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}.dump(
      -1, ' ', false, json::error_handler_t::replace);
}

std::array<uint8_t, kMessageDataHeaderSize> message_data_header(uint32_t subscription_id, uint64_t receive_time_ns) {
  std::array<uint8_t, kMessageDataHeaderSize> header{};
  header[0] = 0x01;
  put_le(header, 1, subscription_id, 4);
  put_le(header, 5, receive_time_ns, 8);
  return header;
}

std::array<uint8_t, 9> time_frame(uint64_t time_ns) {
  std::array<uint8_t, 9> frame{};
  frame[0] = 0x02;
  put_le(frame, 1, time_ns, 8);
  return frame;
}

ClientRequest parse_client_request(const std::string& text) {
  const json message = json::parse(text, nullptr, false);
  if (message.is_discarded() || !message.is_object()) throw ProtocolError("a text message must be a JSON object");
  const auto op = message.find("op");
  if (op == message.end() || !op->is_string()) throw ProtocolError("a message needs an 'op' string");
  ClientRequest request;
  if (*op == "subscribe") {
    request.op = ClientRequest::Op::Subscribe;
    for (const auto& entry : array_field(message, "subscriptions")) {
      if (!entry.is_object()) throw ProtocolError("each subscription must be an object");
      request.subscriptions.push_back({id_field(entry, "id"), id_field(entry, "channelId")});
    }
  } else if (*op == "unsubscribe") {
    request.op = ClientRequest::Op::Unsubscribe;
    for (const auto& id : array_field(message, "subscriptionIds")) {
      if (!id.is_number_unsigned() || id.get<uint64_t>() > UINT32_MAX)
        throw ProtocolError("'subscriptionIds' must hold unsigned 32-bit integers");
      request.subscription_ids.push_back(id.get<uint32_t>());
    }
  } else {
    throw ProtocolError("op '" + op->get<std::string>() + "' is not offered by this server (subscribe, unsubscribe)");
  }
  return request;
}

}  // namespace scanbus::foxglove_bridge
