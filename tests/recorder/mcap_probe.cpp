// Test helper for recordings: publishes known samples of every catalogue type and writes
// their CDR bytes down, or receives samples and compares them, byte for byte and in order,
// with such a list.
//   mcap_probe publish COUNT EXPECTED   one topic per type, COUNT samples each, RELIABLE
//   mcap_probe receive EXPECTED SECONDS exit 0 when everything arrived intact and in order
//   mcap_probe burst COUNT RAYS keep_all|keep_last
//                                       COUNT LaserScans on rt/scan as fast as write() takes
//                                       them, RELIABLE with an unbounded (keep_all) or a
//                                       5-sample (keep_last) writer queue; prints how many
//   mcap_probe stamps FILE STAMP...    writes an MCAP file of one FluidPressure on /pressure
//                                       per STAMP (s), in the order given
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "cdr.hpp"
#include "raw_endpoints.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/recorder/mcap_writer.hpp"
#include "scanbus/recorder/ros2msg.hpp"
#include "scanbus/service.hpp"
#include "scanbus/typed_topics.hpp"

using namespace scanbus;

namespace {

template <class T, class = void>
struct HasHeader : std::false_type {};
template <class T>
struct HasHeader<T, std::void_t<decltype(std::declval<T&>().header())>> : std::true_type {};
template <class T, class = void>
struct HasClock : std::false_type {};
template <class T>
struct HasClock<T, std::void_t<decltype(std::declval<T&>().clock())>> : std::true_type {};
template <class T, class = void>
struct HasRequestId : std::false_type {};
template <class T>
struct HasRequestId<T, std::void_t<decltype(std::declval<T&>().request_id())>> : std::true_type {};

// Sample `i`: its stamp and a frame of varying length, so samples differ in bytes and size.
template <class Sample>
Sample known_sample(uint32_t i) {
  Sample sample;
  const std::string frame = "frame_" + std::to_string(i) + std::string(i % 37, 'x');
  if constexpr (HasHeader<Sample>::value) {
    sample.header().stamp().sec(static_cast<int32_t>(i));
    sample.header().stamp().nanosec(i * 1000);
    sample.header().frame_id(frame);
  } else if constexpr (HasClock<Sample>::value) {
    sample.clock().sec(static_cast<int32_t>(i));
    sample.clock().nanosec(i * 1000);
  } else if constexpr (HasRequestId<Sample>::value) {
    sample.request_id(i);
    sample.client(frame);
  } else {
    sample.transforms().resize(i % 4 + 1);
    for (auto& transform : sample.transforms()) transform.child_frame_id(frame);
  }
  return sample;
}

std::string hex(const uint8_t* data, size_t size) {
  static const char digits[] = "0123456789abcdef";
  std::string out;
  for (size_t i = 0; i < size; ++i) out += {digits[data[i] >> 4], digits[data[i] & 15]};
  return out;
}

// The catalogue's durability (a transient-local reader ignores volatile writers),
// reliable, every sample kept.
QosSettings lossless(const TopicInfo& info) { return {true, info.qos.transient_local, true, 10}; }

// One catalogue topic per type.
std::vector<const TopicInfo*> topic_per_type() {
  std::set<std::string> types;
  std::vector<const TopicInfo*> topics;
  for (const auto& info : topic_catalogue())
    if (types.insert(info.type).second) topics.push_back(&info);
  return topics;
}

// Serialized by the generated code (to_cdr pads with zeros to 4 bytes, as DDS sends it;
// the generated writer would leave stale bytes in alignment gaps) and published raw: the
// bytes on the wire are exactly the ones written to EXPECTED.
template <class PubSubType>
void publish_type(Participant& participant, const TopicInfo& info, uint32_t count, std::ostream& expected) {
  recorder::RawWriter writer(participant, info.name, info.type, writer_qos(lossless(info)));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (writer.matched_readers() == 0) {
    if (std::chrono::steady_clock::now() > deadline)
      throw std::runtime_error(info.name + ": no reader matched within 20 s");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  for (uint32_t i = 0; i < count; ++i) {
    const recorder::RawSample bytes = recorder::to_cdr<PubSubType>(known_sample<typename PubSubType::type>(i));
    expected << info.name << " " << hex(bytes.data(), bytes.size()) << "\n";
    if (writer.write(bytes) != recorder::RawWriter::Result::Written)
      throw std::runtime_error(info.name + ": write refused");
  }
  if (!writer.wait_for_acknowledgments(std::chrono::seconds(20)))
    throw std::runtime_error(info.name + ": not acknowledged within 20 s");
}

int publish(uint32_t count, const std::string& expected_path) {
  Participant participant(dds_settings_from_config(Config::parse("", "")), "mcap_probe/publish");
  std::ofstream expected(expected_path);
  for (const TopicInfo* info : topic_per_type()) {
    if (!visit_message_type(info->type, [&](auto tag) {
          publish_type<typename decltype(tag)::type>(participant, *info, count, expected);
        }))
      throw std::runtime_error("no generated type " + info->type);
  }
  return 0;
}

int receive(const std::string& expected_path, double seconds) {
  std::map<std::string, std::vector<std::string>> expected;
  std::ifstream in(expected_path);
  for (std::string topic, bytes; in >> topic >> bytes;) expected[topic].push_back(bytes);
  Participant participant(dds_settings_from_config(Config::parse("", "")), "mcap_probe/receive");
  std::mutex mutex;
  std::map<std::string, std::vector<std::string>> received;
  std::vector<std::unique_ptr<recorder::RawReader>> readers;
  for (const auto& [topic, samples] : expected) {
    readers.push_back(
        std::make_unique<recorder::RawReader>(participant, topic, topic_info(topic).type, lossless(topic_info(topic)),
                                              [&, topic = topic](const auto& sample, const auto&) {
                                                std::lock_guard<std::mutex> lock(mutex);
                                                received[topic].push_back(hex(sample.data(), sample.size()));
                                              }));
  }
  std::cout << "ready" << std::endl;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  auto complete = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& [topic, samples] : expected)
      if (received[topic].size() < samples.size()) return false;
    return true;
  };
  while (!complete() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // extra samples would show now
  readers.clear();
  int failures = 0;
  for (const auto& [topic, samples] : expected) {
    const auto& got = received[topic];
    size_t first_difference = 0;
    while (first_difference < std::min(got.size(), samples.size()) &&
           got[first_difference] == samples[first_difference])
      ++first_difference;
    const bool same = got == samples;
    if (!same && first_difference < std::min(got.size(), samples.size()))
      std::cout << "  expected " << samples[first_difference] << "\n  received " << got[first_difference] << "\n";
    failures += same ? 0 : 1;
    std::cout << (same ? "ok   " : "FAIL ") << topic << ": " << got.size() << " of " << samples.size() << " samples"
              << (same ? ", byte-identical, in order"
                       : ", first difference at sample " + std::to_string(first_difference))
              << "\n";
  }
  return failures == 0 ? 0 : 1;
}

int burst(uint32_t count, uint32_t rays, const std::string& history) {
  Participant participant(dds_settings_from_config(Config::parse("", "")), "mcap_probe/burst");
  Writer<sensor_msgs::msg::LaserScanPubSubType> writer(participant, topics::kScan,
                                                       QosSettings{true, false, history == "keep_all", 5});
  if (!writer.wait_for_readers(1, std::chrono::seconds(20)))
    throw std::runtime_error("no reader on rt/scan within 20 s");
  sensor_msgs::msg::LaserScan scan;
  scan.header().frame_id("laser");
  scan.ranges(std::vector<float>(rays, 3.0f));
  // The first sample is acknowledged before the burst: a writer's losses count from its
  // first sample that arrives (docs/recording.md), as the recorder cannot tell earlier ones
  // from samples written before it joined.
  uint32_t published = writer.write(scan) ? 1 : 0;
  writer.wait_for_acknowledgments(std::chrono::seconds(10));
  for (uint32_t i = 1; i < count; ++i) {
    scan.header().stamp().sec(static_cast<int32_t>(i));
    published += writer.write(scan) ? 1 : 0;
  }
  // The last samples are delivered before the writer goes (a KEEP_LAST writer keeps them).
  writer.wait_for_acknowledgments(std::chrono::seconds(30));
  std::cout << "{\"published\": " << published << "}" << std::endl;
  return 0;
}

int stamps(const std::string& path, const std::vector<double>& seconds) {
  recorder::McapWriter writer(path, {});
  const std::string type = recorder::ros_type_of_dds_type("sensor_msgs::msg::dds_::FluidPressure_");
  const uint16_t schema = writer.add_schema(type, "ros2msg", recorder::Ros2MsgCatalogue::scanbus().schema(type));
  const uint16_t channel = writer.add_channel(schema, "/pressure", "cdr", {});
  uint32_t sequence = 0;
  for (const double stamp : seconds) {
    sensor_msgs::msg::FluidPressure pressure;
    pressure.header().stamp(to_stamp(stamp));
    pressure.fluid_pressure(101325 - sequence);
    const auto bytes = recorder::to_cdr<sensor_msgs::msg::FluidPressurePubSubType>(pressure);
    const auto nanoseconds = static_cast<uint64_t>(stamp * 1e9);
    writer.write(channel, sequence++, nanoseconds, nanoseconds, bytes.data(), bytes.size());
  }
  writer.close();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "publish" && argc == 4) return publish(static_cast<uint32_t>(std::stoul(argv[2])), argv[3]);
    if (mode == "receive" && argc == 4) return receive(argv[2], std::stod(argv[3]));
    if (mode == "burst" && argc == 5 && (std::string(argv[4]) == "keep_all" || std::string(argv[4]) == "keep_last"))
      return burst(static_cast<uint32_t>(std::stoul(argv[2])), static_cast<uint32_t>(std::stoul(argv[3])), argv[4]);
    if (mode == "stamps" && argc >= 3) {
      std::vector<double> seconds;
      for (int i = 3; i < argc; ++i) seconds.push_back(std::stod(argv[i]));
      return stamps(argv[2], seconds);
    }
    std::cerr
        << "usage: mcap_probe publish COUNT EXPECTED | receive EXPECTED SECONDS | burst COUNT RAYS keep_all|keep_last"
           " | stamps FILE STAMP...\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "mcap_probe: " << error.what() << "\n";
    return 1;
  }
}
