#include "cloud_window_client.hpp"

#include <unistd.h>

#include <ctime>
#include <mutex>

#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"

namespace scanbus::cloud_assembly {

std::optional<sensor_msgs::msg::PointCloud2> request_window_cloud(Participant& participant, double begin, double end,
                                                                  double timeout, std::string& problem) {
  const uint64_t id = static_cast<uint64_t>(getpid()) << 32 | static_cast<uint64_t>(time(nullptr) & 0xFFFFFFFF);
  const std::string client = "scanbus/cloud/" + std::to_string(getpid());
  std::mutex mutex;
  std::optional<scanbus::msg::AssembleReply> reply;
  Reader<scanbus::msg::AssembleReplyPubSubType> replies(participant, topics::kAssembleReply,
                                                        [&](const auto& r, const auto&) {
                                                          if (r.request_id() != id || r.client() != client) return;
                                                          std::lock_guard<std::mutex> lock(mutex);
                                                          reply = r;
                                                        });
  Writer<scanbus::msg::AssembleRequestPubSubType> requests(participant, topics::kAssembleRequest);
  // Both directions must be matched, or the reply could be sent before anyone listens.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  const auto waiting = [&] { return std::chrono::steady_clock::now() < deadline; };
  while ((requests.matched_readers() == 0 || replies.matched_writers() == 0) && waiting())
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (requests.matched_readers() == 0 || replies.matched_writers() == 0) {
    problem = "no cloud_assembly answers on rt/cloud/assemble_request";
    return std::nullopt;
  }
  scanbus::msg::AssembleRequest request;
  request.request_id(id);
  request.client(client);
  request.begin(to_stamp(begin));
  request.end(to_stamp(end));
  requests.write(request);
  while (waiting()) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (reply) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::lock_guard<std::mutex> lock(mutex);
  if (!reply) {
    problem = "no reply within the timeout";
    return std::nullopt;
  }
  if (reply->status() != scanbus::msg::AssembleReply_Constants::OK) {
    problem = "cloud_assembly: " + reply->message();
    return std::nullopt;
  }
  return reply->cloud();
}

}  // namespace scanbus::cloud_assembly
