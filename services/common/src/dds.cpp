#include "scanbus/dds.hpp"

#include "scanbus/service.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/log/Log.hpp>
#include <fastdds/dds/log/StdoutErrConsumer.hpp>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <typeinfo>

namespace scanbus {

namespace dds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

DdsSettings dds_settings_from_config(const Config& section) {
  DdsSettings settings;
  settings.profile_file = section.text("profile_file", "");
  settings.profile = section.text("profile", settings.profile);
  settings.domain = static_cast<int>(section.integer("domain", 0, 0, 232));
  if (const char* file = std::getenv("SCANBUS_DDS_PROFILE_FILE")) settings.profile_file = file;
  if (const char* name = std::getenv("SCANBUS_DDS_PROFILE")) settings.profile = name;
  if (const char* domain = std::getenv("SCANBUS_DOMAIN_ID")) {
    try {
      settings.domain = std::stoi(domain);
    } catch (const std::exception&) {
      throw ConfigError(std::string("SCANBUS_DOMAIN_ID: must be a whole number, got '") + domain + "'");
    }
    if (settings.domain < 0 || settings.domain > 232)
      throw ConfigError("SCANBUS_DOMAIN_ID: must be between 0 and 232, got " + std::string(domain));
  }
  return settings;
}

std::map<std::string, std::string> dds_environment(const DdsSettings& settings) {
  // An empty file is the built-in profile, also when this process's environment names one.
  return {{"SCANBUS_DOMAIN_ID", std::to_string(settings.domain)},
          {"SCANBUS_DDS_PROFILE_FILE", settings.profile_file},
          {"SCANBUS_DDS_PROFILE", settings.profile}};
}

namespace {

// SCANBUS_DDS_LOG=warning (or error): Fast DDS's own log from that level on, on
// stderr (stdout is data for `scanbus echo` and --json); its shared-memory transport says
// there when it finds a port dead and replaces it, or drops buffers because its segment is
// full. Unset: Fast DDS's default, errors only.
void set_middleware_log_level() {
  static const bool done = [] {
    const char* level = std::getenv("SCANBUS_DDS_LOG");
    if (!level) return true;
    // No "info": Debian's Fast DDS 2.9.1 is built without its info messages.
    const std::map<std::string, dds::Log::Kind> kinds = {{"error", dds::Log::Kind::Error},
                                                         {"warning", dds::Log::Kind::Warning}};
    const auto kind = kinds.find(level);
    if (kind == kinds.end())
      throw ConfigError(std::string("SCANBUS_DDS_LOG: must be error or warning, got '") + level + "'");
    auto to_stderr = std::make_unique<dds::StdoutErrConsumer>();
    to_stderr->stderr_threshold(dds::Log::Kind::Info);
    dds::Log::ClearConsumers();
    dds::Log::RegisterConsumer(std::move(to_stderr));
    dds::Log::SetVerbosity(kind->second);
    return true;
  }();
  (void)done;
}

}  // namespace

Participant::Participant(const DdsSettings& settings, const std::string& name,
                         dds::DomainParticipantListener* listener) {
  set_middleware_log_level();
  auto* factory = dds::DomainParticipantFactory::get_instance();
  dds::DomainParticipantQos qos;
  if (!settings.profile_file.empty()) {
    static std::mutex loading;
    static std::set<std::string> loaded_files;  // again would make Fast DDS log errors
    std::lock_guard<std::mutex> lock(loading);
    if (!loaded_files.count(settings.profile_file)) {
      if (factory->load_XML_profiles_file(settings.profile_file) != ReturnCode_t::RETCODE_OK)
        throw DdsError(settings.profile_file + ": cannot load Fast DDS XML profiles");
      loaded_files.insert(settings.profile_file);
    }
    if (factory->get_participant_qos_from_profile(settings.profile, qos) != ReturnCode_t::RETCODE_OK)
      throw DdsError(settings.profile_file + ": no participant profile '" + settings.profile + "'");
  } else {
    // Once per process: loading the same profiles again makes Fast DDS log errors.
    static const bool loaded = [factory] {
      const std::string xml = embedded_localhost_profile();
      return factory->load_XML_profiles_string(xml.c_str(), xml.size()) == ReturnCode_t::RETCODE_OK;
    }();
    if (!loaded || factory->get_participant_qos_from_profile(settings.profile, qos) != ReturnCode_t::RETCODE_OK)
      throw DdsError("built-in DDS profile has no participant profile '" + settings.profile + "'");
  }
  qos.name(name);
  participant_ = factory->create_participant(settings.domain, qos, listener, dds::StatusMask::none());
  if (!participant_) throw DdsError("cannot create DDS participant on domain " + std::to_string(settings.domain));
  publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);
  if (!publisher_ || !subscriber_) {
    release();  // no destructor runs for a constructor that throws: no participant left behind
    throw DdsError("cannot create DDS publisher or subscriber");
  }
}

Participant::~Participant() { release(); }

void Participant::release() {
  if (!participant_) return;
  participant_->set_listener(nullptr);  // no discovery callback into an owner being destroyed
  participant_->delete_contained_entities();
  dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  participant_ = nullptr;
}

dds::Topic* Participant::topic(const std::string& name, dds::TopicDataType* type) {
  std::lock_guard<std::mutex> lock(mutex_);
  dds::TypeSupport support(type);  // owns `type` from here on
  // One participant, one implementation per type name: a reader would otherwise decode
  // samples with another type's code (generated vs raw bytes) into the wrong object.
  const dds::TypeSupport registered = participant_->find_type(support.get_type_name());
  if (!registered.empty() && typeid(*registered.get()) != typeid(*support.get()))
    throw DdsError("type " + support.get_type_name() + " is already registered with other code in this participant");
  if (auto found = topics_.find(name); found != topics_.end()) {
    if (found->second->get_type_name() != support.get_type_name())
      throw DdsError("topic '" + name + "' already has type " + found->second->get_type_name());
    return found->second;
  }
  if (registered.empty() && support.register_type(participant_) != ReturnCode_t::RETCODE_OK)
    throw DdsError("cannot register type " + support.get_type_name());
  dds::Topic* topic = participant_->create_topic(name, support.get_type_name(), dds::TOPIC_QOS_DEFAULT);
  if (!topic)
    throw DdsError("cannot create topic '" + name + "' of type " + support.get_type_name() +
                   " (under DDS Security: is this identity granted it?)");
  topics_[name] = topic;
  return topic;
}

void Participant::set_qos_overrides(const Config& qos_section) {
  for (const auto& name : qos_section.keys()) {
    const TopicInfo* info = find_topic(name);
    if (!info)
      throw ConfigError(qos_section.origin() + ": key '" + qos_section.path_of(name) + "' names an unknown topic");
    qos_overrides_[name] = qos_from_config(qos_section, *info);
  }
}

void Participant::count_lost(const std::string& topic, uint64_t samples) {
  std::lock_guard<std::mutex> lock(lost_mutex_);
  lost_by_topic_[topic] += samples;
}

std::map<std::string, uint64_t> Participant::lost_by_topic() const {
  std::lock_guard<std::mutex> lock(lost_mutex_);
  return lost_by_topic_;
}

uint64_t Participant::lost() const {
  uint64_t total = 0;
  for (const auto& [topic, samples] : lost_by_topic()) total += samples;
  return total;
}

uint64_t SequenceGaps::add(const dds::SampleInfo& info) {
  const int64_t sequence = info.sample_identity.sequence_number().to64long();
  const auto [last, first] = last_.try_emplace(info.sample_identity.writer_guid(), sequence);
  const uint64_t gap = !first && sequence > last->second + 1 ? static_cast<uint64_t>(sequence - last->second - 1) : 0;
  last->second = std::max(last->second, sequence);
  return gap;
}

QosSettings Participant::qos(const std::string& topic_name) const {
  if (auto found = qos_overrides_.find(topic_name); found != qos_overrides_.end()) return found->second;
  return topic_info(topic_name).qos;
}

namespace {

template <class EndpointQos>
void apply(const QosSettings& qos, EndpointQos& out) {
  out.reliability().kind = qos.reliable ? dds::RELIABLE_RELIABILITY_QOS : dds::BEST_EFFORT_RELIABILITY_QOS;
  out.durability().kind = qos.transient_local ? dds::TRANSIENT_LOCAL_DURABILITY_QOS : dds::VOLATILE_DURABILITY_QOS;
  out.history().kind = qos.keep_all ? dds::KEEP_ALL_HISTORY_QOS : dds::KEEP_LAST_HISTORY_QOS;
  out.history().depth = qos.depth;
  // Unbounded sequences (clouds, scans) report a bogus maximum size: let the history grow.
  out.endpoint().history_memory_policy = eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
}

}  // namespace

dds::DataWriterQos writer_qos(const QosSettings& qos) {
  dds::DataWriterQos out = dds::DATAWRITER_QOS_DEFAULT;
  apply(qos, out);
  return out;
}

dds::DataReaderQos reader_qos(const QosSettings& qos) {
  dds::DataReaderQos out = dds::DATAREADER_QOS_DEFAULT;
  apply(qos, out);
  return out;
}

dds::DataWriter* create_writer(Participant& participant, const std::string& topic, dds::TopicDataType* type,
                               const QosSettings& qos) {
  return create_writer(participant, topic, type, writer_qos(qos), describe(qos));
}

dds::DataWriter* create_writer(Participant& participant, const std::string& topic, dds::TopicDataType* type,
                               const dds::DataWriterQos& qos, const std::string& qos_text) {
  dds::DataWriter* writer = participant.publisher()->create_datawriter(participant.topic(topic, type), qos);
  if (!writer)
    throw DdsError("cannot create writer on '" + topic + "' (" + qos_text +
                   "; under DDS Security: is this identity granted it? scanbus security permissions)");
  return writer;
}

dds::DataReader* create_reader(Participant& participant, const std::string& topic, dds::TopicDataType* type,
                               const QosSettings& qos, dds::DataReaderListener* listener) {
  dds::DataReader* reader = participant.subscriber()->create_datareader(participant.topic(topic, type), reader_qos(qos),
                                                                        listener, dds::StatusMask::data_available());
  if (!reader)
    throw DdsError("cannot create reader on '" + topic + "' (" + describe(qos) +
                   "; under DDS Security: is this identity granted it? scanbus security permissions)");
  return reader;
}

void linger_for_lagging_readers(double seconds) {
  if (seconds > 0) StopSignal::wait_for(std::chrono::milliseconds(static_cast<long>(seconds * 1000)));
}

void delete_writer(Participant& participant, dds::DataWriter* writer) {
  participant.publisher()->delete_datawriter(writer);
}

void delete_reader(Participant& participant, dds::DataReader* reader) {
  // Detach first so no callback runs into a half-destroyed Reader.
  reader->set_listener(nullptr);
  participant.subscriber()->delete_datareader(reader);
}

}  // namespace scanbus
