// DDS endpoints that carry a sample as its serialized bytes (CDR with the 4-byte
// encapsulation header, exactly what MCAP's `cdr` encoding stores) under any registered
// type name: the recorder needs no generated code per type, and a replayed sample goes
// out byte for byte as it was recorded.
#pragma once

#include <fastdds/dds/topic/TopicDataType.hpp>

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "scanbus/dds.hpp"

namespace scanbus::recorder {

using RawSample = std::vector<uint8_t>;

class RawType : public eprosima::fastdds::dds::TopicDataType {
 public:
  using type = RawSample;
  explicit RawType(const std::string& type_name);
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override;
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override;
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override;
  void* createData() override { return new RawSample(); }
  void deleteData(void* data) override { delete static_cast<RawSample*>(data); }
  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
};

// A Reader of raw bytes under the given registered type name.
class RawReader : public Reader<RawType> {
 public:
  RawReader(Participant& participant, const std::string& topic, const std::string& type_name, const QosSettings& qos,
            Handler handler)
      : Reader<RawType>(participant, topic, new RawType(type_name), qos, std::move(handler)) {}
};

class RawWriter {
 public:
  RawWriter(Participant& participant, const std::string& topic, const std::string& type_name,
            const eprosima::fastdds::dds::DataWriterQos& qos);
  ~RawWriter();
  RawWriter(const RawWriter&) = delete;
  RawWriter& operator=(const RawWriter&) = delete;

  enum class Result { Written, QueueFull, Refused };
  // QueueFull: the queue stayed full for the QoS's max_blocking_time (try again);
  // Refused: the sample cannot go out (too short to be CDR, or DDS refused it).
  Result write(const RawSample& sample);
  size_t matched_readers() const;
  bool wait_for_acknowledgments(std::chrono::milliseconds timeout);
  const std::string& topic() const { return topic_; }

 private:
  Participant& participant_;
  std::string topic_;
  eprosima::fastdds::dds::DataWriter* writer_;
};

}  // namespace scanbus::recorder
