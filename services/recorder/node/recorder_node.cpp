#include "recorder_node.hpp"

#include "recording.hpp"

namespace scanbus::recorder {

namespace {

// Health counts the raw participant's losses while it lives.
class LossWatch {
 public:
  LossWatch(HealthReporter& health, const Participant& participant) : health_(health), participant_(participant) {
    health_.watch_losses(participant_);
  }
  ~LossWatch() { health_.unwatch_losses(participant_); }
  LossWatch(const LossWatch&) = delete;
  LossWatch& operator=(const LossWatch&) = delete;

 private:
  HealthReporter& health_;
  const Participant& participant_;
};

class RecorderService : public Service {
 public:
  RecorderService(ServiceContext& context, RecorderSettings settings)
      : context_(context), settings_(std::move(settings)) {}

  int run() override {
    // A participant of its own: its raw readers register catalogue type names (Health's
    // among them) that the service's participant already holds with generated code.
    Participant raw(dds_settings_from_config(context_.config.section("dds")), "scanbus/recorder/raw");
    raw.set_qos_overrides(context_.config.section("qos"));
    LossWatch losses(context_.health, raw);
    // The file is created here, not in the factory, so --check-config writes nothing.
    Recording recording(raw, settings_, context_.log);
    auto& messages = context_.health.counter("messages_recorded");
    auto& bytes = context_.health.counter("bytes_recorded");
    while (!StopSignal::wait_for(std::chrono::milliseconds(200))) {
      messages = recording.messages();
      bytes = recording.bytes();
      if (const std::string failure = recording.failure(); !failure.empty()) {
        context_.health.error(failure);  // FAILED would need a restart anyway: exit and say why
        context_.log->error("recording stopped: {}", failure);
        return 1;
      }
    }
    recording.stop();
    messages = recording.messages();
    context_.health.publish_now();  // the last count of messages and losses
    return 0;
  }

 private:
  ServiceContext& context_;
  RecorderSettings settings_;
};

}  // namespace

std::unique_ptr<Service> make_recorder(ServiceContext& context) {
  return std::make_unique<RecorderService>(context, recorder_settings_from_config(context.config.section("recorder")));
}

}  // namespace scanbus::recorder
