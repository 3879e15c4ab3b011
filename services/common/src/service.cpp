#include "scanbus/service.hpp"

#include <signal.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>

#include "scanbus/clock.hpp"

namespace scanbus {

namespace {

std::mutex stop_mutex;
std::condition_variable stop_changed;
std::atomic<bool> stop_requested{false};

}  // namespace

void StopSignal::install() {
  static std::once_flag once;
  std::call_once(once, [] {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    std::thread([set] {
      int signal_number = 0;
      sigwait(&set, &signal_number);
      request();
    }).detach();
  });
}

void StopSignal::request() {
  {
    std::lock_guard<std::mutex> lock(stop_mutex);
    stop_requested = true;
  }
  stop_changed.notify_all();
}

bool StopSignal::requested() { return stop_requested; }

bool StopSignal::wait_for(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(stop_mutex);
  return stop_changed.wait_for(lock, timeout, [] { return stop_requested.load(); });
}

HealthReporter::HealthReporter(Participant& participant, std::string service, std::chrono::milliseconds period,
                               std::shared_ptr<spdlog::logger> log)
    : watched_{&participant},
      log_(std::move(log)),
      writer_(participant, topics::kHealth),
      service_(std::move(service)),
      period_(period),
      state_(scanbus::msg::Health_Constants::STARTING) {
  thread_ = std::thread([this] { loop(); });
}

HealthReporter::~HealthReporter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    state_ = scanbus::msg::Health_Constants::STOPPING;
  }
  wake_.notify_all();
  thread_.join();
  publish_now();
}

std::atomic<uint64_t>& HealthReporter::counter(const std::string& name) {
  std::lock_guard<std::mutex> lock(mutex_);
  return find_counter(name);
}

std::atomic<uint64_t>& HealthReporter::find_counter(const std::string& name) {
  for (auto& entry : counters_)
    if (entry.first == name) return entry.second;
  counters_.emplace_back(std::piecewise_construct, std::forward_as_tuple(name), std::forward_as_tuple(0));
  return counters_.back().second;
}

void HealthReporter::set_state(uint8_t state) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (state_ == state) return;
    state_ = state;
  }
  publish_now();
}

void HealthReporter::error(const std::string& message) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_error_ = message;
    if (state_ == scanbus::msg::Health_Constants::OK) state_ = scanbus::msg::Health_Constants::DEGRADED;
  }
  publish_now();
}

void HealthReporter::recovered() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (state_ != scanbus::msg::Health_Constants::DEGRADED) return;
    state_ = scanbus::msg::Health_Constants::OK;
  }
  publish_now();
}

void HealthReporter::watch_losses(const Participant& participant) {
  std::lock_guard<std::mutex> lock(mutex_);
  watched_.push_back(&participant);
}

void HealthReporter::unwatch_losses(const Participant& participant) {
  std::lock_guard<std::mutex> lock(mutex_);
  watched_.erase(std::remove(watched_.begin(), watched_.end(), &participant), watched_.end());
}

std::string HealthReporter::note_losses() {
  uint64_t lost = 0;
  std::string topics;
  for (const Participant* participant : watched_)
    for (const auto& [topic, samples] : participant->lost_by_topic()) {
      lost += samples;
      topics += (topics.empty() ? "" : ", ") + topic + " " + std::to_string(samples);
    }
  if (lost <= reported_lost_) return "";
  reported_lost_ = lost;
  find_counter("samples_lost") = lost;
  const auto now = std::chrono::steady_clock::now();
  if (now - loss_logged_ < std::chrono::seconds(5)) return "";
  loss_logged_ = now;
  return std::to_string(lost) + " samples lost before reaching " + service_ + " (" + topics + ")";
}

void HealthReporter::publish_now() {
  scanbus::msg::Health sample;
  std::string loss_message;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    loss_message = note_losses();
    sample.header().stamp(now_stamp());
    sample.service(service_);
    char host[256] = {};
    gethostname(host, sizeof(host) - 1);
    sample.host(host);
    sample.pid(static_cast<uint32_t>(getpid()));
    sample.state(state_);
    sample.uptime(std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count());
    for (const auto& entry : counters_) {
      scanbus::msg::Counter counter;
      counter.name(entry.first);
      counter.value(entry.second.load());
      sample.counters().push_back(counter);
    }
    sample.last_error(last_error_);
  }
  writer_.write(sample);
  if (!loss_message.empty()) log_->warn("{}", loss_message);
}

void HealthReporter::loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    lock.unlock();
    publish_now();
    lock.lock();
    wake_.wait_for(lock, period_, [this] { return stopping_; });
  }
}

std::shared_ptr<spdlog::logger> make_logger(const std::string& service, const std::string& level) {
  auto logger = std::make_shared<spdlog::logger>(service, std::make_shared<spdlog::sinks::stderr_sink_mt>());
  // key=value lines: greppable and machine-parsable without a log shipper.
  logger->set_pattern("ts=%Y-%m-%dT%H:%M:%S.%e level=%l service=%n msg=\"%v\"");
  logger->set_level(spdlog::level::from_str(level));
  return logger;
}

int run_service(const std::string& name, const std::string& config_path, const ServiceFactory& factory,
                bool check_only) {
  StopSignal::install();
  std::shared_ptr<spdlog::logger> log = make_logger(name, "info");
  try {
    const Config config = config_path.empty() ? Config::parse("", "(built-in defaults)") : Config::load(config_path);
    const Config service = config.section("service");
    const auto period =
        std::chrono::milliseconds(static_cast<int>(1000.0 * service.number("health_period", 1.0, 0.05, 60.0)));
    log->set_level(spdlog::level::from_str(
        service.choice("log_level", "info", {"trace", "debug", "info", "warn", "error", "off"})));
    const DdsSettings dds = dds_settings_from_config(config.section("dds"));
    Participant participant(dds, "scanbus/" + name);
    participant.set_qos_overrides(config.section("qos"));
    HealthReporter health(participant, name, period, log);
    ServiceContext context{name, config, participant, health, log};
    std::unique_ptr<Service> instance = factory(context);
    config.check_all_read();
    if (check_only) {
      std::cout << (config_path.empty() ? "built-in defaults" : config_path) << ": valid config for " << name << "\n";
      return 0;
    }
    health.set_state(scanbus::msg::Health_Constants::OK);
    log->info("started (domain {}, profile {})", dds.domain,
              dds.profile_file.empty() ? "built-in localhost" : dds.profile_file);
    const int code = instance->run();
    log->info("stopping");
    instance.reset();
    return code;
  } catch (const ConfigError& e) {
    std::cerr << "scanbus " << name << ": config error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "scanbus " << name << ": " << e.what() << "\n";
    return 1;
  }
}

int service_main(const std::string& name, int argc, char** argv, const ServiceFactory& factory) {
  CLI::App app{"scanbus " + name + " service"};
  std::string config_path;
  bool check_only = false;
  app.add_option("-c,--config", config_path, "YAML config file (defaults built in)");
  app.add_flag("--check-config", check_only, "Validate the config and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return run_service(name, config_path, factory, check_only);
}

}  // namespace scanbus
