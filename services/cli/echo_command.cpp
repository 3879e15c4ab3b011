#include <unistd.h>

#include <atomic>
#include <iostream>
#include <mutex>

#include "commands.hpp"
#include "scanbus/json.hpp"
#include "scanbus/service.hpp"

namespace scanbus::cli {

namespace {

struct EchoOptions {
  DdsOptions dds;
  std::string topic;
  std::string type;
  long count = 0;
  double timeout = 0;
};

// Prints samples until `count` arrived, the timeout passed (exit 1 if short), or a signal.
template <class PubSubType>
int echo(Participant& participant, const EchoOptions& options, const QosSettings& qos) {
  std::mutex output;
  std::atomic<long> received{0};
  Reader<PubSubType> reader(participant, options.topic, qos, [&](const auto& sample, const auto&) {
    std::lock_guard<std::mutex> lock(output);
    if (options.count > 0 && received >= options.count) return;
    std::cout << nlohmann::json(sample).dump() << std::endl;
    if (++received == options.count) StopSignal::request();
  });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout);
  while (!StopSignal::wait_for(std::chrono::milliseconds(50))) {
    if (options.timeout > 0 && std::chrono::steady_clock::now() > deadline) break;
  }
  if (const uint64_t lost = participant.lost())
    std::cerr << "scanbus echo: " << options.topic << ": " << lost
              << " samples lost before reaching echo (gaps in the writers' sequence numbers)\n";
  if (options.count > 0 && received < options.count) {
    std::cerr << "scanbus echo: " << options.topic << ": received " << received << " of " << options.count
              << " samples before the timeout\n";
    return 1;
  }
  return 0;
}

int run_echo(const EchoOptions& options) {
  StopSignal::install();
  const TopicInfo* known = find_topic(options.topic);
  const std::string type = !options.type.empty() ? options.type : known ? known->type : "";
  if (type.empty()) {
    std::cerr << "scanbus echo: unknown topic '" << options.topic << "': give its type with --type\n";
    return 2;
  }
  // Unknown topics: best effort and volatile match any writer.
  const QosSettings qos = known ? known->qos : QosSettings{false, false, false, 100};
  Participant participant(options.dds.settings(), "scanbus/echo");
  int code = 2;
  if (!visit_message_type(type,
                          [&](auto tag) { code = echo<typename decltype(tag)::type>(participant, options, qos); })) {
    std::cerr << "scanbus echo: unknown type '" << type << "'\n";
  }
  return code;
}

}  // namespace

void add_echo_command(CLI::App& app, int& exit_code) {
  static EchoOptions options;
  auto* command = app.add_subcommand("echo", "Subscribe to a topic and print each sample as one JSON line");
  command->add_option("topic", options.topic, "Topic name, e.g. rt/scanner/cloud")->required();
  command->add_option("--type", options.type, "Registered type name, for topics not in the catalogue");
  command->add_option("-n,--count", options.count, "Stop after this many samples (exit 1 if fewer arrive)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--timeout", options.timeout, "Stop after this many seconds (0: never)")
      ->check(CLI::NonNegativeNumber);
  add_dds_options(*command, options.dds);
  on_run(*command, exit_code, [] { return run_echo(options); });
}

}  // namespace scanbus::cli
