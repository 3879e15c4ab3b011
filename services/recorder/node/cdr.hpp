// A generated message to and from its CDR bytes (encapsulation header included, padded to
// 4 bytes as DDS carries it): what MCAP's `cdr` messages hold.
#pragma once

#include <fastdds/rtps/common/SerializedPayload.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace scanbus::recorder {

template <class PubSubType>
std::vector<uint8_t> to_cdr(const typename PubSubType::type& sample) {
  PubSubType type;
  auto* data = const_cast<typename PubSubType::type*>(&sample);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(data)() + 4);
  if (!type.serialize(data, &payload)) throw std::runtime_error(std::string("cannot serialize a ") + type.getName());
  std::vector<uint8_t> bytes(payload.data, payload.data + payload.length);
  bytes.resize((bytes.size() + 3) / 4 * 4, 0);
  return bytes;
}

// Throws std::runtime_error naming the type when the bytes do not decode as one.
template <class PubSubType>
typename PubSubType::type from_cdr(const uint8_t* data, size_t size) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<uint32_t>(size));
  std::memcpy(payload.data, data, size);
  payload.length = static_cast<uint32_t>(size);
  typename PubSubType::type sample;
  if (!type.deserialize(&payload, &sample))
    throw std::runtime_error(std::string("bytes that do not decode as ") + type.getName());
  return sample;
}

}  // namespace scanbus::recorder
