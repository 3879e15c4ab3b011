#include "raw_endpoints.hpp"

#include <cstring>

namespace scanbus::recorder {

namespace dds = eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::SerializedPayload_t;
using eprosima::fastrtps::types::ReturnCode_t;

RawType::RawType(const std::string& type_name) {
  setName(type_name.c_str());
  m_typeSize = 64 * 1024;  // the first reservation; payloads grow (PREALLOCATED_WITH_REALLOC)
  m_isGetKeyDefined = false;
  auto_fill_type_object(false);
  auto_fill_type_information(false);
}

bool RawType::serialize(void* data, SerializedPayload_t* payload) {
  const auto& sample = *static_cast<RawSample*>(data);
  if (sample.size() < 4 || sample.size() > payload->max_size) return false;
  std::memcpy(payload->data, sample.data(), sample.size());
  payload->length = static_cast<uint32_t>(sample.size());
  payload->encapsulation = (sample[1] & 1) ? CDR_LE : CDR_BE;  // the representation identifier's endianness bit
  return true;
}

bool RawType::deserialize(SerializedPayload_t* payload, void* data) {
  auto& sample = *static_cast<RawSample*>(data);
  sample.assign(payload->data, payload->data + payload->length);
  return true;
}

std::function<uint32_t()> RawType::getSerializedSizeProvider(void* data) {
  return [data] { return static_cast<uint32_t>(static_cast<RawSample*>(data)->size()); };
}

RawWriter::RawWriter(Participant& participant, const std::string& topic, const std::string& type_name,
                     const dds::DataWriterQos& qos)
    : participant_(participant), topic_(topic) {
  writer_ = participant.publisher()->create_datawriter(participant.topic(topic, new RawType(type_name)), qos);
  if (!writer_) throw DdsError("cannot create a writer on '" + topic + "' of type " + type_name);
}

RawWriter::~RawWriter() { delete_writer(participant_, writer_); }

RawWriter::Result RawWriter::write(const RawSample& sample) {
  if (sample.size() < 4) return Result::Refused;  // not even a CDR encapsulation header
  const auto code = writer_->write(const_cast<RawSample*>(&sample), eprosima::fastrtps::rtps::c_InstanceHandle_Unknown);
  if (code == ReturnCode_t::RETCODE_OK) return Result::Written;
  return code == ReturnCode_t::RETCODE_TIMEOUT ? Result::QueueFull : Result::Refused;
}

size_t RawWriter::matched_readers() const {
  dds::PublicationMatchedStatus status;
  writer_->get_publication_matched_status(status);
  return static_cast<size_t>(status.current_count);
}

bool RawWriter::wait_for_acknowledgments(std::chrono::milliseconds timeout) {
  return writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(timeout.count() / 1000.0)) ==
         ReturnCode_t::RETCODE_OK;
}

}  // namespace scanbus::recorder
