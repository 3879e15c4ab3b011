// The bridge's bookkeeping: which topics are offered as channels (a topic is offered while a
// writer of it is seen) and which client subscribes to which channel under which id. The
// node asks it what to send to whom and which DDS readers it needs; nothing here touches DDS
// or a socket. Not thread-safe: the node locks.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scanbus/foxglove_bridge/protocol.hpp"

namespace scanbus::foxglove_bridge {

using ClientId = uint64_t;

class Channels {
 public:
  // Offers a topic; a topic offered again after it was withdrawn gets a new id (a client
  // must not take the new channel for its old subscription). nullopt if already offered.
  std::optional<Channel> offer(const std::string& topic, const std::string& schema_name, const std::string& schema);
  // Withdraws a topic and every subscription to it; its channel id, nullopt if not offered.
  std::optional<uint32_t> withdraw(const std::string& topic);
  std::vector<Channel> offered() const;
  const Channel* find(uint32_t channel_id) const;
  const Channel* find_topic(const std::string& topic) const;

  void add_client(ClientId client);
  void remove_client(ClientId client);
  std::vector<ClientId> clients() const;
  // Empty, or why the request is refused (an unknown channel, an id the client already uses).
  std::string subscribe(ClientId client, const Subscription& subscription);
  std::string unsubscribe(ClientId client, uint32_t subscription_id);

  // Who gets a channel's samples: (client, that client's subscription id).
  std::vector<std::pair<ClientId, uint32_t>> subscribers(uint32_t channel_id) const;
  // The topics some client subscribes to: the ones DDS readers are needed for.
  std::set<std::string> wanted_topics() const;

 private:
  uint32_t next_id_ = 1;
  std::map<uint32_t, Channel> channels_;                         // by id
  std::map<ClientId, std::map<uint32_t, uint32_t>> subscribed_;  // client -> subscription id -> channel id
};

}  // namespace scanbus::foxglove_bridge
