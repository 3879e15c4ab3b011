// Thin typed wrappers over Fast DDS: a participant from an XML profile, writers and readers
// of generated types with QoS from the topic catalogue. Only DDS nodes include this.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "scanbus/config.hpp"
#include "scanbus/topics.hpp"
#include "scanbus/typed_topics.hpp"

namespace scanbus {

class DdsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DdsSettings {
  std::string profile_file;  // Fast DDS XML profiles; empty: the built-in loopback profile
  std::string profile = "localhost";
  int domain = 0;
};

// Samples a reader never got (dropped on the way, or overwritten in a KEEP_LAST history
// before they were taken), from gaps in each writer's sequence numbers. A writer's first
// sample starts its count: what it wrote before the reader matched is not a loss, and a
// gap after the last sample that arrives cannot be seen.
class SequenceGaps {
 public:
  // How many of this sample's writer's samples are missing just before it.
  uint64_t add(const eprosima::fastdds::dds::SampleInfo& info);

 private:
  std::map<eprosima::fastrtps::rtps::GUID_t, int64_t> last_;  // by writer
};

// The loopback-only Fast DDS profile compiled into every binary (config/dds/localhost.xml).
const char* embedded_localhost_profile();

// The `dds` section of a service config; SCANBUS_DDS_PROFILE_FILE, SCANBUS_DDS_PROFILE
// (the participant profile's name) and SCANBUS_DOMAIN_ID override the file, so tests and
// deployments can set every process at once.
DdsSettings dds_settings_from_config(const Config& dds_section);
// Those variables for `settings`: what a process started from here needs to join the same
// domain with the same profile.
std::map<std::string, std::string> dds_environment(const DdsSettings& settings);

class Participant {
 public:
  // `listener` (it must outlive the participant) hears discovery from the first moment:
  // set later, it would miss the endpoints found meanwhile.
  Participant(const DdsSettings& settings, const std::string& name,
              eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  eprosima::fastdds::dds::Topic* topic(const std::string& name, eprosima::fastdds::dds::TopicDataType* type);
  eprosima::fastdds::dds::Publisher* publisher() { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() { return subscriber_; }
  eprosima::fastdds::dds::DomainParticipant* get() { return participant_; }
  // QoS of a topic: catalogue default, overridden by the config's qos section.
  QosSettings qos(const std::string& topic_name) const;
  void set_qos_overrides(const Config& qos_section);
  bool has_qos_override(const std::string& topic_name) const { return qos_overrides_.count(topic_name) > 0; }
  // Samples this participant's readers lost (SequenceGaps), by topic; the readers count.
  void count_lost(const std::string& topic, uint64_t samples);
  std::map<std::string, uint64_t> lost_by_topic() const;
  uint64_t lost() const;

 private:
  void release();  // deletes the participant and everything in it
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  std::map<std::string, QosSettings> qos_overrides_;
  std::mutex mutex_;
  mutable std::mutex lost_mutex_;
  std::map<std::string, uint64_t> lost_by_topic_;
};

eprosima::fastdds::dds::DataWriterQos writer_qos(const QosSettings& qos);
eprosima::fastdds::dds::DataReaderQos reader_qos(const QosSettings& qos);

// Fast DDS entity creation that throws instead of returning nullptr.
eprosima::fastdds::dds::DataWriter* create_writer(Participant& participant, const std::string& topic,
                                                  eprosima::fastdds::dds::TopicDataType* type, const QosSettings& qos);
// With Fast DDS's own QoS, for what QosSettings does not say (a bounded KEEP_ALL queue).
eprosima::fastdds::dds::DataWriter* create_writer(Participant& participant, const std::string& topic,
                                                  eprosima::fastdds::dds::TopicDataType* type,
                                                  const eprosima::fastdds::dds::DataWriterQos& qos,
                                                  const std::string& qos_text = "its own QoS");
eprosima::fastdds::dds::DataReader* create_reader(Participant& participant, const std::string& topic,
                                                  eprosima::fastdds::dds::TopicDataType* type, const QosSettings& qos,
                                                  eprosima::fastdds::dds::DataReaderListener* listener);
void delete_writer(Participant& participant, eprosima::fastdds::dds::DataWriter* writer);
void delete_reader(Participant& participant, eprosima::fastdds::dds::DataReader* reader);

// Waits `seconds` (less on a stop signal) before a process that wrote a stream exits.
// Fast DDS 2.9.1 (Debian's) leaves a reader deaf for good when it comes, after the writing
// process has exited, to a sample that process put in shared memory: the writer's segment
// is gone, and the reader retries that sample forever, behind it everything else (fixed
// upstream in 2.6.6, 2.10.2, 2.11.2 and 2.12, not in 2.9; docs/architecture.md). Readers
// lagging behind the stream read it all while the segment lives.
void linger_for_lagging_readers(double seconds);

template <class PubSubType>
class Writer {
 public:
  using Sample = typename PubSubType::type;

  // From the catalogue (typed_topics.hpp): only a topic of this type compiles.
  Writer(Participant& participant, const Topic<PubSubType>& topic) : Writer(participant, std::string(topic.name)) {}
  Writer(Participant& participant, const Topic<PubSubType>& topic, const QosSettings& qos)
      : Writer(participant, std::string(topic.name), qos) {}
  Writer(Participant& participant, const std::string& topic) : Writer(participant, topic, participant.qos(topic)) {}
  Writer(Participant& participant, const std::string& topic, const QosSettings& qos)
      : participant_(participant), topic_(topic), writer_(create_writer(participant, topic, new PubSubType(), qos)) {}
  Writer(Participant& participant, const std::string& topic, const eprosima::fastdds::dds::DataWriterQos& qos)
      : participant_(participant), topic_(topic), writer_(create_writer(participant, topic, new PubSubType(), qos)) {}
  ~Writer() { delete_writer(participant_, writer_); }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // False when Fast DDS refused the sample (e.g. a reliable writer's queue stayed full).
  bool write(const Sample& sample) { return writer_->write(const_cast<Sample*>(&sample)); }
  size_t matched_readers() const {
    eprosima::fastdds::dds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return static_cast<size_t>(status.current_count);
  }
  // Readers matched so far, those gone since included: it grows when a reader joins.
  size_t readers_matched_ever() const {
    eprosima::fastdds::dds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return static_cast<size_t>(status.total_count);
  }
  bool wait_for_readers(size_t count, std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (matched_readers() < count) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  }
  // Blocks until reliable readers acknowledged everything written, or the timeout.
  bool wait_for_acknowledgments(std::chrono::milliseconds timeout) {
    return writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(timeout.count() / 1000.0)) ==
           ReturnCode_OK();
  }
  const std::string& topic() const { return topic_; }

 private:
  static eprosima::fastrtps::types::ReturnCode_t ReturnCode_OK() {
    return eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }
  Participant& participant_;
  std::string topic_;
  eprosima::fastdds::dds::DataWriter* writer_;
};

// Calls a handler for each valid sample, on Fast DDS's listener thread; samples that never
// came are counted in the participant (Participant::lost_by_topic).
template <class PubSubType>
class Reader : private eprosima::fastdds::dds::DataReaderListener {
 public:
  using Sample = typename PubSubType::type;
  using Handler = std::function<void(const Sample&, const eprosima::fastdds::dds::SampleInfo&)>;

  // From the catalogue (typed_topics.hpp): only a topic of this type compiles.
  Reader(Participant& participant, const Topic<PubSubType>& topic, Handler handler)
      : Reader(participant, std::string(topic.name), std::move(handler)) {}
  Reader(Participant& participant, const Topic<PubSubType>& topic, const QosSettings& qos, Handler handler)
      : Reader(participant, std::string(topic.name), qos, std::move(handler)) {}
  Reader(Participant& participant, const std::string& topic, Handler handler)
      : Reader(participant, topic, participant.qos(topic), std::move(handler)) {}
  Reader(Participant& participant, const std::string& topic, const QosSettings& qos, Handler handler)
      : Reader(participant, topic, new PubSubType(), qos, std::move(handler)) {}
  // With a type object of its own (owned from here on): the recorder's raw bytes under any name.
  Reader(Participant& participant, const std::string& topic, eprosima::fastdds::dds::TopicDataType* type,
         const QosSettings& qos, Handler handler)
      : participant_(participant),
        topic_(topic),
        handler_(std::move(handler)),
        reader_(create_reader(participant, topic, type, qos, this)) {}
  ~Reader() { delete_reader(participant_, reader_); }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  size_t matched_writers() const {
    eprosima::fastdds::dds::SubscriptionMatchedStatus status;
    reader_->get_subscription_matched_status(status);
    return static_cast<size_t>(status.current_count);
  }

 private:
  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    eprosima::fastdds::dds::SampleInfo info;
    while (reader->take_next_sample(&sample_, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      // A dispose or unregister uses a sequence number too: not a gap.
      if (info.sample_identity.writer_guid() != eprosima::fastrtps::rtps::GUID_t::unknown())
        if (const uint64_t lost = gaps_.add(info)) participant_.count_lost(topic_, lost);
      if (info.valid_data) handler_(sample_, info);
    }
  }

  Participant& participant_;
  std::string topic_;
  SequenceGaps gaps_;  // Fast DDS calls one reader's listener one call at a time
  Handler handler_;
  Sample sample_;  // reused: large clouds are not reallocated per sample
  eprosima::fastdds::dds::DataReader* reader_;
};

}  // namespace scanbus
