// End-to-end DDS benchmarks across processes, each beside raw Fast DDS (the same bytes,
// QoS and profile, no scanbus code on the path) as the limit. bench/e2e.sh runs them side
// by side and prints the table in docs/performance.md.
//   dds_e2e_bench latency scanbus|raw REVOLUTIONS
//       A serial line entering scanner I/O to the PointCloud2 leaving it: this process is
//       the device on a pseudo-terminal and the subscriber; the process under test is the
//       scanner_io service (scanbus) or `relay` (raw).
//   dds_e2e_bench throughput scanbus|convert|raw POINTS SECONDS
//       PointCloud2 samples of POINTS points from this process to `subscribe` in another,
//       as fast as a bounded reliable queue takes them: through scanbus's Participant,
//       Writer and Reader (scanbus), also converting points to a PointCloud2 and back at the
//       ends as the services do (convert), or raw Fast DDS (raw).
// Internal roles, started by the two above:
//   dds_e2e_bench relay PTY POINTS      reads serial lines; on each revolution's end
//                                        writes a prebuilt cloud with raw Fast DDS
//   dds_e2e_bench subscribe MODE         receives until 1.5 s pass without a sample
// Every result is one JSON object on stdout.
#include <unistd.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

#include <algorithm>
#include <condition_variable>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "protocol.h"
#include "room_cloud.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/launch/system.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"
#include "scanbus/sim/pty_device.hpp"
#include "scanbus/typed_topics.hpp"
#include "scanbus_msgs/PointCloud2PubSubTypes.h"
#include "serial_port.hpp"

using Clock = std::chrono::steady_clock;
using Cloud = sensor_msgs::msg::PointCloud2;
using CloudType = sensor_msgs::msg::PointCloud2PubSubType;
using nlohmann::json;

namespace scanbus::bench {
namespace {

namespace dds = ::eprosima::fastdds::dds;

constexpr const char* kScanCloudTopic = topics::kScannerCloud.name;
constexpr const char* kThroughputTopic = "rt/bench/cloud";
constexpr uint32_t kMeasurementsPerRevolution = 150;  // 20 RPM at 50 Hz (firmware/PROTOCOL.md)
constexpr uint32_t kRevolutionsPerScan = 27;

DdsSettings dds_settings() { return dds_settings_from_config(Config::parse("", "")); }

// Throughput QoS on both sides: reliable, KEEP_ALL, and a writer queue of 8 samples, so a
// full queue makes write() wait for acknowledgements (flow control, nothing dropped).
const QosSettings kThroughputQos{true, false, true, 8};

dds::DataWriterQos throughput_writer_qos() {
  dds::DataWriterQos qos = writer_qos(kThroughputQos);
  qos.resource_limits().max_samples = kThroughputQos.depth;
  qos.resource_limits().max_samples_per_instance = kThroughputQos.depth;
  qos.reliability().max_blocking_time = eprosima::fastrtps::Duration_t(1.0);
  return qos;
}

// A participant, topic and endpoints straight from Fast DDS, with the profile every
// scanbus participant loads.
class RawEndpoints {
 public:
  explicit RawEndpoints(const std::string& topic) {
    auto* factory = dds::DomainParticipantFactory::get_instance();
    const std::string xml = embedded_localhost_profile();
    dds::DomainParticipantQos qos;
    if (factory->load_XML_profiles_string(xml.c_str(), xml.size()) != ReturnCode::RETCODE_OK ||
        factory->get_participant_qos_from_profile(dds_settings().profile, qos) != ReturnCode::RETCODE_OK)
      throw DdsError("cannot load the loopback profile");
    participant_ = factory->create_participant(dds_settings().domain, qos);
    if (!participant_) throw DdsError("cannot create a raw participant");
    type_.register_type(participant_);
    topic_ = participant_->create_topic(topic, type_.get_type_name(), dds::TOPIC_QOS_DEFAULT);
    publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
    subscriber_ = participant_->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);
    if (!topic_ || !publisher_ || !subscriber_) throw DdsError("cannot create a raw topic, publisher or subscriber");
  }
  ~RawEndpoints() {
    participant_->delete_contained_entities();
    dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
  dds::DataWriter* writer(const dds::DataWriterQos& qos) {
    dds::DataWriter* writer = publisher_->create_datawriter(topic_, qos);
    if (!writer) throw DdsError("cannot create a raw writer");
    return writer;
  }
  dds::DataReader* reader(const dds::DataReaderQos& qos, dds::DataReaderListener* listener) {
    dds::DataReader* reader = subscriber_->create_datareader(topic_, qos, listener, dds::StatusMask::data_available());
    if (!reader) throw DdsError("cannot create a raw reader");
    return reader;
  }

 private:
  using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;
  dds::DomainParticipant* participant_ = nullptr;
  dds::TypeSupport type_{new CloudType()};
  dds::Topic* topic_ = nullptr;
  dds::Publisher* publisher_ = nullptr;
  dds::Subscriber* subscriber_ = nullptr;
};

bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

size_t matched(dds::DataWriter* writer) {
  dds::PublicationMatchedStatus status;
  writer->get_publication_matched_status(status);
  return static_cast<size_t>(status.current_count);
}

// Points of a scanned room (room_cloud.hpp), as a service holds them before publishing.
std::vector<CloudPoint> room_points(uint32_t count) {
  const std::vector<uint8_t> bytes = room_cloud_points(count, 1);
  std::vector<CloudPoint> points(count);
  for (uint32_t i = 0; i < count; ++i) std::memcpy(points[i].position.data(), &bytes[16ull * i], 12);
  return points;
}

// The last JSON object a child printed into its log.
json child_result(const ChildProcess& child) {
  std::ifstream log(child.log_path());
  std::string line, last;
  while (std::getline(log, line))
    if (!line.empty() && line.front() == '{') last = line;
  if (last.empty()) throw std::runtime_error(child.name() + " printed no result (see " + child.log_path() + ")");
  return json::parse(last);
}

// Children of the scanbus command this benchmark was built with; their configs and logs go
// with them.
launch::System children() {
  const std::string self = own_executable();
  return launch::System({self.substr(0, self.rfind('/')) + "/../services/cli/scanbus",
                         "/tmp/scanbus_e2e_" + std::to_string(getpid()), dds_settings(), true});
}

json percentiles(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  auto at = [&](double share) {
    return values[std::min(values.size() - 1, static_cast<size_t>(share * values.size()))];
  };
  return {{"samples", values.size()},
          {"median_us", at(0.5)},
          {"p90_us", at(0.9)},
          {"p99_us", at(0.99)},
          {"max_us", values.back()}};
}

// ---- latency: the device end of a pseudo-terminal and a subscriber on rt/scanner/cloud ----

class Device {
 public:
  void write(const std::string& bytes) {
    for (size_t written = 0; written < bytes.size();) {
      const size_t count = pty_.write(bytes.substr(written));
      written += count;
      if (count == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));  // the client's buffer is full
      pty_.read();  // commands from the host (RES, START, STATUS) are not answered
    }
  }
  void send(char tag, std::initializer_list<uint32_t> fields) {
    char line[scanner::kMaxLine];
    const std::vector<uint32_t> values(fields);
    write(std::string(line, scanner::format_fields(line, tag, values.data(), static_cast<int>(values.size()))));
  }
  void hello() {
    char line[scanner::kMaxLine] = "H scanbus-scanner 1 0.1.0";
    write(std::string(line, scanner::finish_line(line, static_cast<int>(std::strlen(line)))));
  }
  // One revolution's measurements at a pitch (hundredths of a degree), all at 3 m.
  void revolution(uint32_t pitch) {
    std::string lines;
    char line[scanner::kMaxLine];
    for (uint32_t i = 0; i < kMeasurementsPerRevolution; ++i, ++sequence_) {
      const uint32_t fields[] = {sequence_, yaw_ += 36000 / kMeasurementsPerRevolution, pitch, 300, 120};
      lines.append(line, scanner::format_fields(line, 'M', fields, 5));
    }
    write(lines);
  }
  const std::string& path() const { return pty_.path(); }

 private:
  sim::PtyDevice pty_{""};
  uint32_t sequence_ = 0, yaw_ = 0;
};

int latency(const std::string& mode, int revolutions) {
  Participant participant(dds_settings(), "e2e_latency");
  std::mutex mutex;
  std::condition_variable arrived;
  uint64_t clouds = 0;
  Clock::time_point arrival;
  Reader<CloudType> reader(participant, kScanCloudTopic, [&](const Cloud&, const auto&) {
    const auto now = Clock::now();
    std::lock_guard<std::mutex> lock(mutex);
    arrival = now;
    ++clouds;
    arrived.notify_all();
  });
  Device device;
  launch::System system = children();
  launch::ServiceConfig config;
  config.log_level = "warn";
  config.settings["port"] = device.path();
  config.settings["scans"] = 0;
  ChildProcess& child =
      mode == "scanbus" ? system.start("scanner_io", config)
                        : system.start_program("relay", own_executable(),
                                               {"relay", device.path(), std::to_string(kMeasurementsPerRevolution)});
  system.wait_until([&] { return reader.matched_writers() > 0; }, 20,
                    child.name() + " did not publish " + kScanCloudTopic);
  device.hello();
  std::vector<double> latencies;
  const int warm_up = 20;
  for (int lap = 0; lap < revolutions + warm_up; ++lap) {
    const auto index = static_cast<uint32_t>(lap) % kRevolutionsPerScan;
    const uint32_t pitch = 4200 + 300 * index;
    device.revolution(pitch);
    std::this_thread::sleep_for(std::chrono::milliseconds(15));  // as a device: the lap's end comes after its lines
    system.check();
    std::unique_lock<std::mutex> lock(mutex);
    const uint64_t expected = clouds + 1;
    lock.unlock();
    const auto sent = Clock::now();
    device.send('L', {index, pitch});
    lock.lock();
    if (!arrived.wait_for(lock, std::chrono::seconds(2), [&] { return clouds >= expected; }))
      throw std::runtime_error("no PointCloud2 within 2 s of revolution " + std::to_string(lap) + "'s end (see " +
                               child.log_path() + ")");
    if (lap >= warm_up) latencies.push_back(std::chrono::duration<double, std::micro>(arrival - sent).count());
    lock.unlock();
    if (index + 1 == kRevolutionsPerScan) {
      device.send('D', {static_cast<uint32_t>(lap) / kRevolutionsPerScan, kRevolutionsPerScan});
      std::this_thread::sleep_for(std::chrono::milliseconds(30));  // the scan's cloud goes out, untimed
    }
  }
  std::cout << json{{"mode", mode}, {"points", kMeasurementsPerRevolution}, {"latency", percentiles(latencies)}}
            << std::endl;
  return 0;
}

// The raw side of `latency`: lines in through the same serial reader, and at each
// revolution's end ("L ...") a cloud of the same size out, already built.
int relay(const std::string& port_path, uint32_t points) {
  StopSignal::install();  // before Fast DDS starts its threads
  RawEndpoints endpoints(kScanCloudTopic);
  dds::DataWriter* writer = endpoints.writer(writer_qos(topic_info(kScanCloudTopic).qos));
  Cloud cloud = to_point_cloud2(room_points(points), "scanner", now_stamp());
  scanner_io::SerialPort port(port_path, 115200);
  std::string error;
  if (!port.open(error)) throw std::runtime_error(error);
  std::vector<std::string> lines;
  while (!StopSignal::requested()) {
    lines.clear();
    if (!port.read_lines(lines, 100)) throw std::runtime_error(port_path + ": the line closed");
    for (const auto& line : lines) {
      if (line.empty() || line.front() != 'L') continue;
      cloud.header().stamp(now_stamp());
      writer->write(&cloud);
    }
  }
  return 0;
}

// ---- throughput: this process publishes, a `subscribe` child receives ----

int throughput(const std::string& mode, uint32_t points, double seconds) {
  launch::System system = children();
  ChildProcess& subscriber =
      system.start_program("subscribe", own_executable(), {"subscribe", mode}, launch::Lifetime::RunsToEnd);
  const std::vector<CloudPoint> source = room_points(points);
  const auto deadline = [&](Clock::time_point start) {
    return Clock::now() - start < std::chrono::duration<double>(seconds);
  };
  uint64_t published = 0, retried = 0;
  // A full queue that stays full for max_blocking_time refuses the sample: write it again.
  auto publish = [&](const auto& write) {
    while (!write()) ++retried;
    ++published;
  };
  Cloud cloud = to_point_cloud2(source, "map", now_stamp());
  if (mode != "raw") {
    Participant participant(dds_settings(), "e2e_publisher");
    Writer<CloudType> writer(participant, kThroughputTopic, throughput_writer_qos());
    if (!writer.wait_for_readers(1, std::chrono::seconds(20))) throw std::runtime_error("no subscriber within 20 s");
    for (const auto start = Clock::now(); deadline(start);) {
      // `convert`: as a service publishes, its points become a new PointCloud2 each time.
      if (mode == "convert")
        cloud = to_point_cloud2(source, "map", now_stamp());
      else
        cloud.header().stamp(now_stamp());
      publish([&] { return writer.write(cloud); });
    }
    writer.wait_for_acknowledgments(std::chrono::seconds(30));
  } else {
    RawEndpoints endpoints(kThroughputTopic);
    dds::DataWriter* writer = endpoints.writer(throughput_writer_qos());
    if (!wait_until([&] { return matched(writer) > 0; }, std::chrono::seconds(20)))
      throw std::runtime_error("no subscriber within 20 s");
    for (const auto start = Clock::now(); deadline(start);) {
      cloud.header().stamp(now_stamp());
      publish([&] { return writer->write(&cloud); });
    }
    writer->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(30.0));
  }
  if (!wait_until([&] { return subscriber.exited().has_value(); }, std::chrono::seconds(10)))
    throw std::runtime_error("the subscriber did not finish (see " + subscriber.log_path() + ")");
  json result = child_result(subscriber);
  result["published"] = published;
  result["retried_writes"] = retried;  // write() returned false (queue full) and was repeated
  result["points"] = points;
  result["mode"] = mode;
  std::cout << result << std::endl;
  return 0;
}

class Receipts {
 public:
  void add(size_t bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    last_ = Clock::now();
    if (samples_++ == 0) first_ = last_;
    bytes_ = bytes;
  }
  // Waits for a first sample (60 s), then until 1.5 s pass without one.
  json wait() {
    wait_until([&] { return count() > 0; }, std::chrono::seconds(60));
    wait_until(
        [&] {
          std::lock_guard<std::mutex> lock(mutex_);
          return Clock::now() - last_ > std::chrono::milliseconds(1500);
        },
        std::chrono::hours(1));
    std::lock_guard<std::mutex> lock(mutex_);
    const double span = std::chrono::duration<double>(last_ - first_).count();
    // Rates over the intervals between the first and the last sample.
    const double rate = samples_ > 1 ? (samples_ - 1) / span : 0;
    return {
        {"received", samples_}, {"sample_bytes", bytes_}, {"samples_per_s", rate}, {"mb_per_s", rate * bytes_ / 1e6}};
  }

 private:
  uint64_t count() {
    std::lock_guard<std::mutex> lock(mutex_);
    return samples_;
  }
  std::mutex mutex_;
  uint64_t samples_ = 0;
  size_t bytes_ = 0;
  Clock::time_point first_, last_;
};

class RawListener : public dds::DataReaderListener {
 public:
  explicit RawListener(Receipts& receipts) : receipts_(receipts) {}
  void on_data_available(dds::DataReader* reader) override {
    dds::SampleInfo info;
    while (reader->take_next_sample(&cloud_, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK)
      if (info.valid_data) receipts_.add(cloud_.data().size());
  }

 private:
  Receipts& receipts_;
  Cloud cloud_;
};

int subscribe(const std::string& mode) {
  Receipts receipts;
  json result;
  if (mode != "raw") {
    Participant participant(dds_settings(), "e2e_subscriber");
    // `convert`: as a service subscribes, every cloud read back into points.
    Reader<CloudType> reader(participant, kThroughputTopic, kThroughputQos, [&](const Cloud& cloud, const auto&) {
      receipts.add(mode == "convert" ? from_point_cloud2(cloud).size() * sizeof(CloudPoint) : cloud.data().size());
    });
    result = receipts.wait();
  } else {
    RawEndpoints endpoints(kThroughputTopic);
    RawListener listener(receipts);
    dds::DataReader* reader = endpoints.reader(reader_qos(kThroughputQos), &listener);
    result = receipts.wait();
    reader->set_listener(nullptr);
  }
  std::cout << result << std::endl;
  return 0;
}

}  // namespace
}  // namespace scanbus::bench

int main(int argc, char** argv) {
  using namespace scanbus::bench;
  const std::vector<std::string> args(argv + 1, argv + argc);
  auto usage = [] {
    std::cerr
        << "usage: dds_e2e_bench latency scanbus|raw REVOLUTIONS | throughput scanbus|convert|raw POINTS SECONDS\n";
    return 2;
  };
  try {
    const bool known_mode = args.size() >= 2 && (args[1] == "scanbus" || args[1] == "raw" || args[1] == "convert");
    if (args.size() >= 2 && args[0] != "relay" && !known_mode) return usage();
    if (args.size() == 3 && args[0] == "latency" && args[1] == "convert") return usage();
    if (args.size() == 3 && args[0] == "latency" && std::stoi(args[2]) > 0) return latency(args[1], std::stoi(args[2]));
    if (args.size() == 4 && args[0] == "throughput")
      return throughput(args[1], static_cast<uint32_t>(std::stoul(args[2])), std::stod(args[3]));
    if (args.size() == 3 && args[0] == "relay") return relay(args[1], static_cast<uint32_t>(std::stoul(args[2])));
    if (args.size() == 2 && args[0] == "subscribe") return subscribe(args[1]);
    return usage();
  } catch (const std::exception& error) {
    std::cerr << "dds_e2e_bench: " << error.what() << "\n";
    return 1;
  }
}
