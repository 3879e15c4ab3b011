// What every scanbus service shares: config loading and validation, a DDS participant,
// periodic Health, structured logs, and a clean stop on SIGINT/SIGTERM.
#pragma once

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "scanbus/config.hpp"
#include "scanbus/dds.hpp"
#include "scanbus_msgs/HealthPubSubTypes.h"

namespace scanbus {

// SIGINT and SIGTERM are blocked in every thread and awaited by one watcher thread, so a
// stop never runs code inside a signal handler. Call install() before starting threads.
class StopSignal {
 public:
  static void install();
  static void request();
  static bool requested();
  // Sleeps up to `timeout`; true when a stop was requested (then immediately).
  static bool wait_for(std::chrono::milliseconds timeout);
};

// Publishes a Health sample every period and on every state change. Samples the
// participant's readers lost (Participant::lost_by_topic) show as the counter
// `samples_lost`, with a log warning naming the topics (at most one per 5 s). A loss
// leaves the state alone: on a best-effort sensor stream it is counted, not a fault.
class HealthReporter {
 public:
  HealthReporter(Participant& participant, std::string service, std::chrono::milliseconds period,
                 std::shared_ptr<spdlog::logger> log);
  ~HealthReporter();
  HealthReporter(const HealthReporter&) = delete;
  HealthReporter& operator=(const HealthReporter&) = delete;

  // A named counter, published with every sample; the reference stays valid.
  std::atomic<uint64_t>& counter(const std::string& name);
  void set_state(uint8_t state);
  // Records the error, marks the service DEGRADED and publishes at once.
  void error(const std::string& message);
  // Back from DEGRADED to OK once the service has shown its fault is over (last_error keeps it).
  void recovered();
  void publish_now();
  // Also counts the losses of another participant's readers (the recorder's own) until
  // unwatch_losses(); the reporter's participant is always counted.
  void watch_losses(const Participant& participant);
  void unwatch_losses(const Participant& participant);

 private:
  void loop();
  std::atomic<uint64_t>& find_counter(const std::string& name);  // mutex_ held
  std::string note_losses();                                     // mutex_ held; what to log, if anything

  std::vector<const Participant*> watched_;  // whose losses are counted
  std::shared_ptr<spdlog::logger> log_;
  Writer<scanbus::msg::HealthPubSubType> writer_;
  std::string service_;
  std::chrono::milliseconds period_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  uint8_t state_;
  std::string last_error_;
  uint64_t reported_lost_ = 0;
  std::chrono::steady_clock::time_point loss_logged_;
  std::deque<std::pair<std::string, std::atomic<uint64_t>>> counters_;
  std::thread thread_;
};

std::shared_ptr<spdlog::logger> make_logger(const std::string& service, const std::string& level);

// What a service's factory gets: its config (the whole file; its own settings are under
// the service's name), the participant, health, and a logger.
struct ServiceContext {
  std::string name;
  const Config& config;
  Participant& participant;
  HealthReporter& health;
  std::shared_ptr<spdlog::logger> log;
};

class Service {
 public:
  virtual ~Service() = default;
  // Works until StopSignal::requested(); returns the process exit code.
  virtual int run() = 0;
};

// Reads config and creates DDS endpoints, without starting work: unknown keys are
// checked after the factory returns and before run().
using ServiceFactory = std::function<std::unique_ptr<Service>(ServiceContext&)>;

// Exit codes: 0 done, 1 runtime failure, 2 bad config or command line. With check_only,
// returns after the config was read and validated.
int run_service(const std::string& name, const std::string& config_path, const ServiceFactory& factory,
                bool check_only = false);

// main() of a service's own executable: `NAME [--config FILE] [--check-config]`.
int service_main(const std::string& name, int argc, char** argv, const ServiceFactory& factory);

}  // namespace scanbus
