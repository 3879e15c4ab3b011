// The scanner path as separate processes: the firmware simulator (or a scripted device) on a
// pseudo-terminal, scanner_io reading it, and this test subscribing over DDS.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <thread>

#include "protocol.h"
#include "scanbus/launch/system.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"
#include "scanbus/sim/pty_device.hpp"
#include "scanbus/sim/room_file.hpp"
#include "scanbus/typed_topics.hpp"

using namespace scanbus;
using namespace std::chrono_literals;

namespace {

constexpr double kNoise = 0.02;  // the simulator's default range sigma

// Everything scanner_io publishes, collected.
class ScannerObserver {
 public:
  explicit ScannerObserver(int domain)
      : participant_(DdsSettings{"", "localhost", domain}, "scanbus/test"),
        batches_(participant_, topics::kScannerSpherical, QosSettings{true, false, true, 1},
                 [this](const auto& batch, const auto&) { locked([&] { batches.push_back(batch); }); }),
        scans_(participant_, topics::kScannerScanCloud,
               [this](const auto& cloud, const auto&) { locked([&] { scans.push_back(from_point_cloud2(cloud)); }); }),
        statuses_(participant_, topics::kScannerStatus, QosSettings{true, false, true, 1},
                  [this](const auto& status, const auto&) { locked([&] { statuses.push_back(status); }); }),
        health_(participant_, topics::kHealth, [this](const auto& health, const auto&) {
          if (health.service() != "scanner_io") return;
          locked([&] {
            health_states.push_back(health.state());
            for (const auto& counter : health.counters()) counters[counter.name()] = counter.value();
          });
        }) {}

  // Waits until `done` holds (checked under the lock) or the timeout; false on timeout.
  bool wait_until(const std::function<bool()>& done, std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {  // checked at least once, even with no time to wait
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (done()) return true;
      }
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(50ms);
    }
  }

  // Called under the lock, from wait_until.
  bool discovered() const { return batches_.matched_writers() > 0 && statuses_.matched_writers() > 0; }

  std::mutex mutex;
  std::vector<scanbus::msg::SphericalScan> batches;
  std::vector<std::vector<CloudPoint>> scans;
  std::vector<scanbus::msg::ScannerStatus> statuses;
  std::map<std::string, uint64_t> counters;
  std::vector<uint8_t> health_states;  // scanner_io's, in order

 private:
  template <class F>
  void locked(F&& f) {
    std::lock_guard<std::mutex> lock(mutex);
    f();
  }
  Participant participant_;
  Reader<scanbus::msg::SphericalScanPubSubType> batches_;
  Reader<sensor_msgs::msg::PointCloud2PubSubType> scans_;
  Reader<scanbus::msg::ScannerStatusPubSubType> statuses_;
  Reader<scanbus::msg::HealthPubSubType> health_;
};

class ScannerPipeline : public ::testing::Test {
 protected:
  void SetUp() override {
    char dir[] = "/tmp/scanbus_pipeline_XXXXXX";
    work_ = mkdtemp(dir);
    link_ = work_ + "/scanner.tty";
  }
  void TearDown() override {
    system_.reset();  // the children stop before their work folder goes
    std::system(("rm -rf " + work_).c_str());
  }

  // Each test on its own domain: ctest runs them in parallel.
  void use_domain(int domain) {
    observer_ = std::make_unique<ScannerObserver>(domain);
    system_ = std::make_unique<launch::System>(launch::SystemSettings{SCANBUS_CLI, work_, {"", "localhost", domain}});
  }

  // scanner_io on the test's device link, looking for it often; `settings` (YAML) over that.
  ChildProcess& start_scanner_io(const std::string& settings = "{}") {
    launch::ServiceConfig config;
    config.health_period = 0.2;
    config.settings["port"] = link_;
    config.settings["reconnect_min"] = 0.05;
    config.settings["reconnect_max"] = 0.5;
    for (const auto& entry : YAML::Load(settings)) config.settings[entry.first.as<std::string>()] = entry.second;
    return system_->start("scanner_io", config);
  }

  // Until then, what scanner_io publishes would not reach our volatile readers.
  void wait_for_discovery() {
    ASSERT_TRUE(observer_->wait_until([&] { return observer_->discovered(); }, 20s)) << "scanner_io not discovered";
  }

  ChildProcess& start_simulator(const std::vector<std::string>& extra) {
    std::vector<std::string> arguments = {"sim", "scanner", "--link", link_};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    ChildProcess& simulator = system_->start_command("sim", arguments);
    for (int i = 0; i < 100 && access(link_.c_str(), F_OK) != 0; ++i) std::this_thread::sleep_for(20ms);
    return simulator;
  }

  std::string log(const std::string& name) {
    std::ifstream in(work_ + "/" + name);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  std::string work_, link_;
  std::unique_ptr<ScannerObserver> observer_;
  std::unique_ptr<launch::System> system_;
};

// What the firmware would send, framed with its own checksum.
std::string framed(const std::string& payload) {
  char line[scanner::kMaxLine];
  payload.copy(line, payload.size());
  scanner::finish_line(line, static_cast<int>(payload.size()));
  return line;
}

void write_all(sim::PtyDevice& device, std::string bytes) {
  for (int i = 0; i < 500 && !bytes.empty(); ++i) {
    bytes.erase(0, device.write(bytes));
    if (!bytes.empty()) std::this_thread::sleep_for(5ms);
  }
  ASSERT_TRUE(bytes.empty()) << "the pty did not take the stream";
}

}  // namespace

TEST_F(ScannerPipeline, FullScanOfTheDefaultRoomArrivesWhole) {
  use_domain(89);
  start_scanner_io("{resolution: 1}");
  wait_for_discovery();
  start_simulator({"--speed", "20", "--dropout", "0", "--seed", "3"});
  ASSERT_TRUE(observer_->wait_until([&] { return !observer_->scans.empty(); }, 60s))
      << log("sim.log") << log("scanner_io.log");
  std::lock_guard<std::mutex> lock(observer_->mutex);

  // Every measurement of the scan, in order, none lost.
  ASSERT_EQ(observer_->batches.size(), 27u);
  uint32_t expected_line = 0;
  size_t in_gate = 0, measurements = 0;
  for (const auto& batch : observer_->batches) {
    EXPECT_EQ(batch.lost(), 0u);
    EXPECT_EQ(batch.first_sequence(), expected_line);
    // 20 RPM at 50 Hz: 150 a revolution (Table 4.2), less the servo's 80 ms settling.
    EXPECT_GE(batch.measurements().size(), 140u);
    EXPECT_LE(batch.measurements().size(), 151u);
    for (const auto& m : batch.measurements()) {
      EXPECT_EQ(m.line(), expected_line++);
      ++measurements;
      if (m.range() >= 0.05f && m.range() <= 40.f) ++in_gate;
    }
  }
  const auto& points = observer_->scans.front();
  EXPECT_EQ(points.size(), in_gate);  // every returned measurement became a point
  EXPECT_GT(in_gate, measurements * 9 / 10);
  EXPECT_EQ(observer_->statuses.back().lost_lines(), 0u);

  // Points lie on the room model's surfaces, within the range noise: Gaussian noise puts
  // 99.73 % within 3 sigma, so allow 0.5 % beyond it and nothing beyond 5 sigma.
  const sim::RoomModel room = sim::load_room_file(std::string(SCANBUS_SOURCE_DIR) + "/config/rooms/thesis_case1.yaml");
  size_t beyond_3_sigma = 0;
  double worst = 0;
  for (const auto& point : points) {
    const double distance = room.distance_to_surface(point.position.cast<double>());
    beyond_3_sigma += distance > 3 * kNoise;
    worst = std::max(worst, distance);
  }
  std::printf("%zu points, %zu beyond 3 sigma (%.2f %%), worst %.3f m from the model\n", points.size(), beyond_3_sigma,
              100.0 * beyond_3_sigma / points.size(), worst);
  EXPECT_LE(beyond_3_sigma, points.size() / 200) << "of " << points.size();
  EXPECT_LT(worst, 5 * kNoise);
}

TEST_F(ScannerPipeline, ReconnectsAfterUnplugAndScansAgain) {
  use_domain(90);
  // Unplugged 20 s into the first scan (1 s real time at x20), back after 1 s.
  ChildProcess& scanner_io = start_scanner_io("{resolution: 2}");
  wait_for_discovery();
  start_simulator({"--speed", "20", "--unplug-at", "20", "--unplug-for", "1"});
  ASSERT_TRUE(observer_->wait_until([&] { return !observer_->scans.empty(); }, 90s))
      << log("sim.log") << log("scanner_io.log");
  EXPECT_TRUE(observer_->wait_until([&] { return observer_->counters["aborted_scans"] >= 1; }, 5s));
  std::lock_guard<std::mutex> lock(observer_->mutex);
  EXPECT_GT(observer_->scans.front().size(), 2000u);  // a whole scan at 28 RPM: 27 x ~105
  const auto disconnected = std::count_if(observer_->statuses.begin(), observer_->statuses.end(), [](const auto& s) {
    return s.state() == scanbus::msg::ScannerStatus_Constants::DISCONNECTED;
  });
  EXPECT_GE(disconnected, 1);
  const bool gap_reported = std::any_of(observer_->statuses.begin(), observer_->statuses.end(), [](const auto& s) {
    return s.message().find("after a gap of") != std::string::npos;
  });
  EXPECT_TRUE(gap_reported);
  EXPECT_FALSE(scanner_io.exited().has_value());
}

// A device plugged in after the back-off has grown long is opened at once: while the device
// node is missing, scanner_io looks for it every reconnect_min. Here the back-off has reached
// 6.4 s when the device appears; without the look-out the next attempt would come about 5 s
// later.
TEST_F(ScannerPipeline, TakesUpAReplugAtOnceWhateverTheBackOff) {
  use_domain(91);
  start_scanner_io("{reconnect_min: 0.1, reconnect_max: 30}");
  wait_for_discovery();
  std::this_thread::sleep_for(7s);  // retries at 0.1, 0.3, 0.7, 1.5, 3.1 and 6.3 s; the next at 12.7 s
  const auto plugged = std::chrono::steady_clock::now();
  start_simulator({"--speed", "20"});
  auto connected = [&] {
    return std::any_of(observer_->statuses.begin(), observer_->statuses.end(),
                       [](const auto& s) { return s.message().rfind("connected", 0) == 0; });
  };
  ASSERT_TRUE(observer_->wait_until(connected, 10s)) << log("scanner_io.log");
  const double after = std::chrono::duration<double>(std::chrono::steady_clock::now() - plugged).count();
  EXPECT_LT(after, 1.5) << "connected " << after << " s after the device appeared\n" << log("scanner_io.log");
  // DEGRADED while the device was missing, OK again once a whole scan came from it (a
  // container whose device appeared late turned healthy only after a restart before).
  const auto degraded = [&] {
    const auto& s = observer_->health_states;
    return std::find(s.begin(), s.end(), scanbus::msg::Health_Constants::DEGRADED) != s.end();
  };
  EXPECT_TRUE(observer_->wait_until(degraded, 1s)) << "no DEGRADED while the device was missing";
  EXPECT_TRUE(observer_->wait_until(
      [&] {
        return !observer_->scans.empty() && !observer_->health_states.empty() &&
               observer_->health_states.back() == scanbus::msg::Health_Constants::OK;
      },
      90s))
      << "not OK again after a whole scan\n"
      << log("scanner_io.log");
}

TEST_F(ScannerPipeline, DamagedStreamIsCountedNeverFatal) {
  use_domain(92);
  sim::PtyDevice device(link_);
  std::string stream = framed("H scanbus-scanner 1 0.1.0");
  for (int line = 0; line < 10; ++line)
    stream += framed("M " + std::to_string(line) + " " + std::to_string(line * 300) + " 4200 250 100");
  stream += "\x01\xff###garbage\n";                                // noise on the line
  stream += framed("M 10 3000 4200 250 100").substr(0, 9) + "\n";  // truncated: line 10 lost
  std::string corrupted = framed("M 11 3300 4200 250 100");
  corrupted[5] = '9';  // bit error: line 11 lost
  stream += corrupted;
  stream += std::string(600, 'Z') + "\n";  // runaway line without an end
  for (int line = 12; line < 20; ++line)
    stream += framed("M " + std::to_string(line) + " " + std::to_string(line * 300) + " 4200 250 100");
  stream += framed("L 0 4200");
  for (int line = 20; line < 30; ++line)
    stream += framed("M " + std::to_string(line) + " " + std::to_string(line * 300) + " 4500 " +
                     (line < 22 ? "1" : "250") + " 100");
  stream += framed("L 1 4500") + framed("D 0 2");
  write_all(device, stream);
  ChildProcess& scanner_io = start_scanner_io("{autostart: false}");
  ASSERT_TRUE(observer_->wait_until([&] { return !observer_->scans.empty(); }, 30s)) << log("scanner_io.log");
  ASSERT_TRUE(observer_->wait_until([&] { return observer_->counters["scans"] == 1; }, 5s));
  // ScannerStatus carries the same counts, once its next periodic sample is out.
  EXPECT_TRUE(observer_->wait_until(
      [&] { return !observer_->statuses.empty() && observer_->statuses.back().malformed_lines() == 3; }, 3s));
  std::lock_guard<std::mutex> lock(observer_->mutex);
  EXPECT_EQ(observer_->scans.front().size(), 10u + 8u + 8u);  // two no-returns (1 cm) kept out
  EXPECT_EQ(observer_->counters["lost_lines"], 2u);
  EXPECT_EQ(observer_->counters["checksum_errors"], 1u);
  EXPECT_EQ(observer_->counters["malformed_lines"], 3u);  // garbage, truncated, runaway
  EXPECT_EQ(observer_->counters["out_of_range"], 2u);
  EXPECT_FALSE(scanner_io.exited().has_value());
  EXPECT_EQ(observer_->statuses.back().checksum_errors(), 1u);
  EXPECT_EQ(observer_->statuses.back().lost_lines(), 2u);
  EXPECT_EQ(observer_->statuses.back().out_of_range(), 2u);
}

TEST_F(ScannerPipeline, CommandsOverDdsStartAndStopTheScanner) {
  use_domain(93);
  start_scanner_io("{autostart: false}");
  wait_for_discovery();
  start_simulator({"--speed", "10"});
  Participant participant(DdsSettings{"", "localhost", 93}, "scanbus/test_commands");
  Writer<scanbus::msg::ScannerCommandPubSubType> commands(participant, topics::kScannerCommand);
  ASSERT_TRUE(commands.wait_for_readers(1, 20s));
  auto send = [&](uint8_t command, uint8_t resolution) {
    scanbus::msg::ScannerCommand sample;
    sample.command(command);
    sample.resolution(resolution);
    ASSERT_TRUE(commands.write(sample));
  };
  std::this_thread::sleep_for(1s);
  EXPECT_FALSE(observer_->wait_until([&] { return !observer_->batches.empty(); }, 0s));  // autostart off: nothing yet
  send(scanbus::msg::ScannerCommand_Constants::SET_RESOLUTION, 2);
  send(scanbus::msg::ScannerCommand_Constants::START, 0);
  ASSERT_TRUE(observer_->wait_until([&] { return !observer_->batches.empty(); }, 20s)) << log("scanner_io.log");
  send(scanbus::msg::ScannerCommand_Constants::STOP, 0);
  ASSERT_TRUE(observer_->wait_until(
      [&] {
        return !observer_->statuses.empty() &&
               observer_->statuses.back().state() == scanbus::msg::ScannerStatus_Constants::IDLE;
      },
      10s));
  size_t batches = 0;
  {
    std::lock_guard<std::mutex> lock(observer_->mutex);
    batches = observer_->batches.size();
    // Resolution 2 is 28 RPM: about 107 measurements a revolution.
    EXPECT_LT(observer_->batches.front().measurements().size(), 110u);
  }
  std::this_thread::sleep_for(1500ms);  // 15 s of device time: it would have done 7 revolutions
  std::lock_guard<std::mutex> lock(observer_->mutex);
  EXPECT_EQ(observer_->batches.size(), batches);
}

TEST_F(ScannerPipeline, LegacyThesisStream) {
  use_domain(94);
  sim::PtyDevice device(link_);
  std::string stream;
  int lines = 0;
  for (int revolution = 0; revolution < 3; ++revolution) {
    stream += "n\n";
    for (int step = 0; step < 60; ++step, ++lines) {
      char line[64];
      std::snprintf(line, sizeof(line), "%.2f %.2f %d\r\n", 1.57 + 0.05 * revolution, step * 0.1, 250 + step);
      stream += line;
    }
  }
  stream += "1.57 x 250\n";  // malformed
  stream += "d\n";
  write_all(device, stream);
  start_scanner_io("{protocol: legacy}");
  ASSERT_TRUE(observer_->wait_until([&] { return !observer_->scans.empty(); }, 30s)) << log("scanner_io.log");
  ASSERT_TRUE(observer_->wait_until([&] { return observer_->counters["malformed_lines"] == 1; }, 5s));
  std::lock_guard<std::mutex> lock(observer_->mutex);
  const auto& points = observer_->scans.front();
  // The thesis's first 'n' opens the scan, so revolutions close at each following 'n' and at 'd'.
  ASSERT_EQ(points.size(), static_cast<size_t>(lines));
  // "1.57 0.00 250": pitch 1.57 rad, yaw 0, 250 cm -> 2.5 m along x.
  EXPECT_NEAR(points.front().position.x(), 2.5 * std::sin(1.57), 1e-4);
  EXPECT_NEAR(points.front().position.z(), 2.5 * std::cos(1.57), 1e-4);
}
