#include "scanbus/foxglove_bridge/channels.hpp"

namespace scanbus::foxglove_bridge {

std::optional<Channel> Channels::offer(const std::string& topic, const std::string& schema_name,
                                       const std::string& schema) {
  if (find_topic(topic)) return std::nullopt;
  Channel channel{next_id_++, topic, schema_name, schema};
  channels_.emplace(channel.id, channel);
  return channel;
}

std::optional<uint32_t> Channels::withdraw(const std::string& topic) {
  const Channel* channel = find_topic(topic);
  if (!channel) return std::nullopt;
  const uint32_t id = channel->id;
  channels_.erase(id);
  for (auto& [client, subscriptions] : subscribed_)
    for (auto sub = subscriptions.begin(); sub != subscriptions.end();)
      sub = sub->second == id ? subscriptions.erase(sub) : std::next(sub);
  return id;
}

std::vector<Channel> Channels::offered() const {
  std::vector<Channel> list;
  for (const auto& [id, channel] : channels_) list.push_back(channel);
  return list;
}

const Channel* Channels::find(uint32_t channel_id) const {
  const auto it = channels_.find(channel_id);
  return it == channels_.end() ? nullptr : &it->second;
}

const Channel* Channels::find_topic(const std::string& topic) const {
  for (const auto& [id, channel] : channels_)
    if (channel.topic == topic) return &channel;
  return nullptr;
}

void Channels::add_client(ClientId client) { subscribed_[client]; }

void Channels::remove_client(ClientId client) { subscribed_.erase(client); }

std::vector<ClientId> Channels::clients() const {
  std::vector<ClientId> list;
  for (const auto& [client, subscriptions] : subscribed_) list.push_back(client);
  return list;
}

std::string Channels::subscribe(ClientId client, const Subscription& subscription) {
  auto& subscriptions = subscribed_[client];
  if (!channels_.count(subscription.channel_id))
    return "subscription " + std::to_string(subscription.id) + ": no channel " +
           std::to_string(subscription.channel_id) + " is advertised";
  if (!subscriptions.emplace(subscription.id, subscription.channel_id).second)
    return "subscription " + std::to_string(subscription.id) + " is already in use";
  return {};
}

std::string Channels::unsubscribe(ClientId client, uint32_t subscription_id) {
  if (subscribed_[client].erase(subscription_id) == 0)
    return "no subscription " + std::to_string(subscription_id) + " to end";
  return {};
}

std::vector<std::pair<ClientId, uint32_t>> Channels::subscribers(uint32_t channel_id) const {
  std::vector<std::pair<ClientId, uint32_t>> list;
  for (const auto& [client, subscriptions] : subscribed_)
    for (const auto& [subscription, channel] : subscriptions)
      if (channel == channel_id) list.emplace_back(client, subscription);
  return list;
}

std::set<std::string> Channels::wanted_topics() const {
  std::set<std::string> topics;
  for (const auto& [client, subscriptions] : subscribed_)
    for (const auto& [subscription, channel] : subscriptions) topics.insert(channels_.at(channel).topic);
  return topics;
}

}  // namespace scanbus::foxglove_bridge
