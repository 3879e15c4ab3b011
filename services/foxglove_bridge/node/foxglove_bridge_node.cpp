#include "foxglove_bridge_node.hpp"

#include <algorithm>
#include <chrono>
#include <set>

#include "raw_endpoints.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/foxglove_bridge/channels.hpp"
#include "scanbus/recorder/ros2msg.hpp"
#include "scanbus/typed_topics.hpp"
#include "websocket_server.hpp"

namespace scanbus::foxglove_bridge {

namespace {

namespace dds = eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::GUID_t;
using eprosima::fastrtps::rtps::WriterDiscoveryInfo;

struct BridgeSettings {
  ServerSettings server;
  bool sim_time = false;  // time from rt/clock (a replay's), offered as the protocol's `time`
};

BridgeSettings bridge_settings_from_config(const Config& section) {
  BridgeSettings settings;
  ServerSettings& server = settings.server;
  server.address = section.text("address", server.address);
  server.port = static_cast<uint16_t>(section.integer("port", server.port, 0, 65535));
  server.client_queue_bytes = static_cast<size_t>(
      section.number("client_queue_size", server.client_queue_bytes / 1048576.0, 1, 65536) * 1048576);
  settings.sim_time = section.flag("sim_time", settings.sim_time);
  return settings;
}

// How far behind a client is, for its status message and the log.
std::string drops_text(const ClientQueue& queue, const std::map<uint32_t, std::string>& topic_of_channel) {
  std::string text =
      std::to_string(queue.dropped) + " messages dropped because this client reads more slowly than they arrive (";
  bool first = true;
  for (const auto& [channel, count] : queue.dropped_by_channel) {
    const auto topic = topic_of_channel.find(channel);
    text += (first ? "" : ", ") + (topic == topic_of_channel.end() ? "?" : topic->second) + " " + std::to_string(count);
    first = false;
  }
  return text + ")";
}

// Several refusals of one request as one status, so a request cannot fill a queue with them.
void add_refusal(std::string& refusals, const std::string& refused) {
  if (!refused.empty()) refusals += (refusals.empty() ? "" : "; ") + refused;
}

class FoxgloveBridge : public Service, public dds::DomainParticipantListener {
 public:
  FoxgloveBridge(ServiceContext& context, BridgeSettings settings)
      : context_(context), settings_(std::move(settings)), session_id_(std::to_string(wall_clock_ns())) {}

  int run() override {
    WebSocketServer server(settings_.server,
                           {[this](ClientId client) { opened(client); },
                            [this](ClientId client, const std::string& text) { request(client, text); },
                            [this](ClientId client, const ClientQueue& last) { closed(client, last); }});
    server_ = &server;  // before any client or DDS callback can use it; the server stops before it goes
    server.start();
    context_.log->info("Foxglove WebSocket server on ws://{}:{}{}", settings_.server.address, server.port(),
                       settings_.sim_time ? ", time from rt/clock" : "");
    if (!is_loopback_address(settings_.server.address))
      context_.log->warn(
          "listening on {}, not loopback: whoever reaches it reads every topic; put TLS and access "
          "control in front (docs/deploy.md)",
          settings_.server.address);
    std::unique_ptr<Reader<rosgraph_msgs::msg::ClockPubSubType>> clock;
    if (settings_.sim_time)
      clock = std::make_unique<Reader<rosgraph_msgs::msg::ClockPubSubType>>(
          context_.participant, topics::kClock, [this](const auto& sample, const auto&) { tick(sample); });
    serve();
    clock.reset();
    server.stop();
    return 0;
  }

  // Writers of catalogue topics come and go with the services (DDS discovery thread).
  void on_publisher_discovery(dds::DomainParticipant*, WriterDiscoveryInfo&& info) override {
    const std::string topic = info.info.topicName().to_string();
    const TopicInfo* known = find_topic(topic);
    if (!known || known->type != info.info.typeName().to_string()) return;  // not ours to decode
    std::lock_guard<std::mutex> lock(mutex_);
    auto& writers = writers_[topic];
    const std::string ros_topic = recorder::ros_topic_of_dds_topic(topic);
    if (info.status == WriterDiscoveryInfo::REMOVED_WRITER) {
      if (writers.erase(info.info.guid()) == 0 || !writers.empty()) return;
      if (const auto id = channels_.withdraw(ros_topic)) {
        latched_.erase(*id);
        to_all(Frame::control(unadvertise({*id})));
      }
      return;
    }
    if (!writers.insert(info.info.guid()).second || writers.size() > 1) return;
    const std::string ros_type = recorder::ros_type_of_dds_type(known->type);
    try {
      if (const auto channel =
              channels_.offer(ros_topic, ros_type, recorder::Ros2MsgCatalogue::scanbus().schema(ros_type))) {
        topic_of_channel_[channel->id] = ros_topic;
        to_all(Frame::control(advertise({*channel})));
      }
    } catch (const recorder::Ros2MsgError& error) {  // a catalogue type without IDL: a build fault, said once
      context_.log->error("{} is not offered: {}", ros_topic, error.what());
    }
  }

 private:
  // The DDS side, until a stop: a participant of its own, listening for writers from its
  // first moment (its raw readers register catalogue type names that the service's
  // participant holds with generated code); its readers go before it.
  void serve() {
    Participant raw(dds_settings_from_config(context_.config.section("dds")), "scanbus/foxglove_bridge/raw", this);
    raw.set_qos_overrides(context_.config.section("qos"));
    struct DropReaders {
      FoxgloveBridge& bridge;
      ~DropReaders() {
        std::lock_guard<std::mutex> lock(bridge.readers_mutex_);
        bridge.readers_.clear();
      }
    } drop_readers{*this};
    while (!StopSignal::wait_for(std::chrono::milliseconds(100))) {
      match_readers(raw);
      report();
    }
  }

  void opened(ClientId client) {
    std::lock_guard<std::mutex> lock(mutex_);
    channels_.add_client(client);
    const std::vector<std::string> capabilities =
        settings_.sim_time ? std::vector<std::string>{"time"} : std::vector<std::string>{};
    server_->send(client, Frame::control(server_info("scanbus foxglove_bridge", capabilities, session_id_)));
    server_->send(client, Frame::control(advertise(channels_.offered())));
    if (sim_now_ > 0) server_->send(client, Frame::time(sim_now_));
    context_.log->info("client {} connected", client);
  }

  void closed(ClientId client, const ClientQueue& last) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto clients = channels_.clients();
    if (std::find(clients.begin(), clients.end(), client) == clients.end()) return;  // never past the handshake
    channels_.remove_client(client);
    dropped_by_gone_clients_ += last.dropped;
    reported_.erase(client);
    context_.log->info("client {} ({}) left", client, last.remote);
  }

  void request(ClientId client, const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string refusals;
    try {
      const ClientRequest request = parse_client_request(text);
      for (const auto& subscription : request.subscriptions) {
        const std::string refused = channels_.subscribe(client, subscription);
        add_refusal(refusals, refused);
        // A latched topic's last sample (the bridge keeps one), as a DDS reader joining late gets it.
        const auto last = latched_.find(subscription.channel_id);
        if (refused.empty() && last != latched_.end())
          server_->send(
              client, Frame::sample(subscription.channel_id, subscription.id, last->second.first, last->second.second));
      }
      for (const uint32_t id : request.subscription_ids) add_refusal(refusals, channels_.unsubscribe(client, id));
    } catch (const ProtocolError& error) {
      refusals = error.what();
    }
    if (!refusals.empty()) server_->send(client, Frame::control(status(StatusLevel::Error, refusals)));
  }

  // DDS readers exactly for the topics some client subscribes to. A reader DDS refuses (a QoS
  // override it rejects, DDS Security) is reported to the clients and not tried again.
  void match_readers(Participant& raw) {
    std::set<std::string> wanted;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto wanted_ros = channels_.wanted_topics();
      for (const auto& ros_topic : wanted_ros) wanted.insert(recorder::dds_topic_of_ros_topic(ros_topic));
      for (auto it = latched_.begin(); it != latched_.end();) {  // a topic no longer read goes stale
        const Channel* channel = channels_.find(it->first);
        it = channel && wanted_ros.count(channel->topic) ? std::next(it) : latched_.erase(it);
      }
    }
    std::lock_guard<std::mutex> lock(readers_mutex_);
    for (auto it = readers_.begin(); it != readers_.end();)
      it = wanted.count(it->first) ? std::next(it) : readers_.erase(it);
    for (const auto& topic : wanted) {
      if (readers_.count(topic) || refused_topics_.count(topic)) continue;
      try {
        const QosSettings qos = raw.qos(topic);
        readers_.emplace(topic, std::make_unique<recorder::RawReader>(
                                    raw, topic, topic_info(topic).type, qos,
                                    [this, topic, latched = qos.transient_local](const recorder::RawSample& sample,
                                                                                 const dds::SampleInfo&) {
                                      forward(topic, latched, sample);
                                    }));
      } catch (const DdsError& error) {
        refused_topics_.insert(topic);
        context_.log->error("{}: no DDS reader: {}", topic, error.what());
        std::lock_guard<std::mutex> clients(mutex_);
        to_all(Frame::control(status(StatusLevel::Error, topic + " cannot be read: " + error.what())));
      }
    }
  }

  // The replay's clock: every client's timeline follows it.
  void tick(const rosgraph_msgs::msg::Clock& sample) {
    std::lock_guard<std::mutex> lock(mutex_);
    sim_now_ = to_nanoseconds(sample.clock());
    to_all(Frame::time(sim_now_));
  }

  // A sample's bytes are copied once and shared by every client's frame; its receive time is
  // the replay's clock under sim_time (once it has ticked).
  void forward(const std::string& topic, bool latched, const recorder::RawSample& sample) {
    const uint64_t wall = wall_clock_ns();
    auto bytes = std::make_shared<const std::vector<uint8_t>>(sample);
    std::lock_guard<std::mutex> lock(mutex_);
    const uint64_t received = settings_.sim_time && sim_now_ > 0 ? sim_now_ : wall;
    const Channel* channel = channels_.find_topic(recorder::ros_topic_of_dds_topic(topic));
    if (!channel) return;
    if (latched) latched_[channel->id] = {received, bytes};
    for (const auto& [client, subscription] : channels_.subscribers(channel->id)) {
      server_->send(client, Frame::sample(channel->id, subscription, received, bytes));
      ++forwarded_;
    }
  }

  // Health counters, and a status (at most one a second) to each client that lost messages.
  void report() {
    const auto queues = server_->queues();
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    const auto clients = channels_.clients();
    uint64_t dropped = dropped_by_gone_clients_;
    for (const auto& queue : queues) {
      if (std::find(clients.begin(), clients.end(), queue.client) == clients.end()) continue;  // left meanwhile
      dropped += queue.dropped;
      auto& reported = reported_[queue.client];
      if (queue.dropped == reported.dropped || now - reported.at < std::chrono::seconds(1)) continue;
      reported = {queue.dropped, now};
      const std::string text = drops_text(queue, topic_of_channel_);
      server_->send(queue.client, Frame::progress(status(StatusLevel::Warning, text)));
      context_.log->warn("client {} ({}): {}", queue.client, queue.remote, text);
    }
    context_.health.counter("clients") = clients.size();
    context_.health.counter("messages_forwarded") = forwarded_;
    context_.health.counter("messages_dropped") = dropped;
  }

  void to_all(const Frame& frame) {
    for (const ClientId client : channels_.clients()) server_->send(client, frame);
  }

  struct Reported {
    uint64_t dropped = 0;
    std::chrono::steady_clock::time_point at;
  };

  ServiceContext& context_;
  const BridgeSettings settings_;
  const std::string session_id_;  // one per run: a client that reconnects sees the same server
  WebSocketServer* server_ = nullptr;
  // Guards everything below it up to readers_mutex_; taken before the server's and a
  // client's locks, never after.
  std::mutex mutex_;
  Channels channels_;
  std::map<std::string, std::set<GUID_t>> writers_;   // by DDS topic
  std::map<uint32_t, std::string> topic_of_channel_;  // every channel ever offered, for drop reports
  std::map<ClientId, Reported> reported_;             // the drops last told to each client
  // The last sample of each latched (transient-local) channel read: (receive time, bytes).
  std::map<uint32_t, std::pair<uint64_t, std::shared_ptr<const std::vector<uint8_t>>>> latched_;
  uint64_t forwarded_ = 0, dropped_by_gone_clients_ = 0;
  uint64_t sim_now_ = 0;                                                 // ns, the last rt/clock (sim_time)
  std::mutex readers_mutex_;                                             // the readers; taken alone, or before mutex_
  std::map<std::string, std::unique_ptr<recorder::RawReader>> readers_;  // by DDS topic
  std::set<std::string> refused_topics_;                                 // DDS would not make their reader
};

}  // namespace

std::unique_ptr<Service> make_foxglove_bridge(ServiceContext& context) {
  const Config section = context.config.section("foxglove_bridge");
  return std::make_unique<FoxgloveBridge>(context, bridge_settings_from_config(section));
}

}  // namespace scanbus::foxglove_bridge
