#include "scanbus/foxglove_bridge/send_queue.hpp"

#include <gtest/gtest.h>

using namespace scanbus::foxglove_bridge;

namespace {

std::shared_ptr<const std::vector<uint8_t>> bytes(size_t size, uint8_t mark) {
  return std::make_shared<const std::vector<uint8_t>>(size, mark);
}

// The marks of the queued samples, in order ('c' for a control message).
std::string contents(SendQueue queue) {
  std::string marks;
  while (auto frame = queue.pop()) marks += frame->payload ? char((*frame->payload)[0]) : 'c';
  return marks;
}

}  // namespace

TEST(SendQueue, AClientThatKeepsUpLosesNothing) {
  SendQueue queue(1000);
  queue.push(Frame::sample(1, 10, 0, bytes(100, 'a')));
  queue.push(Frame::sample(2, 11, 0, bytes(100, 'b')));
  EXPECT_EQ(queue.bytes(), 2 * (100 + kMessageDataHeaderSize));
  EXPECT_EQ(contents(queue), "ab");
  EXPECT_EQ(queue.dropped(), 0u);
}

TEST(SendQueue, OverTheBoundTheSameChannelsOldestGoesFirst) {
  SendQueue queue(400);
  queue.push(Frame::sample(1, 10, 0, bytes(100, 'a')));  // channel 1, oldest
  queue.push(Frame::sample(2, 11, 0, bytes(100, 'b')));  // channel 2
  queue.push(Frame::sample(1, 10, 0, bytes(100, 'c')));
  queue.push(Frame::sample(1, 10, 0, bytes(100, 'd')));  // over 400: 'a' goes, not 'b'
  EXPECT_EQ(contents(queue), "bcd");
  EXPECT_EQ(queue.dropped(), 1u);
  EXPECT_EQ(queue.dropped_by_channel().at(1), 1u);
  EXPECT_EQ(queue.dropped_by_channel().count(2), 0u);
}

TEST(SendQueue, ThenTheOldestOfAnyChannel) {
  SendQueue queue(250);
  queue.push(Frame::sample(1, 10, 0, bytes(100, 'a')));
  queue.push(Frame::sample(2, 11, 0, bytes(100, 'b')));
  queue.push(Frame::sample(3, 12, 0, bytes(100, 'c')));  // channel 3 has nothing older: 'a' goes
  EXPECT_EQ(contents(queue), "bc");
  EXPECT_EQ(queue.dropped_by_channel().at(1), 1u);
}

TEST(SendQueue, ControlMessagesAreNeverDroppedAndOneBigSampleStillGoes) {
  SendQueue queue(1000);
  EXPECT_TRUE(queue.push(Frame::control(std::string(150, '{'))));
  queue.push(Frame::sample(1, 10, 0, bytes(500, 'a')));
  queue.push(Frame::sample(1, 10, 0, bytes(500, 'b')));   // over the bound: 'a' goes
  queue.push(Frame::sample(2, 11, 0, bytes(2000, 'd')));  // larger than the bound: 'b' goes, 'd' stays alone
  EXPECT_EQ(contents(queue), "cd");
  EXPECT_EQ(queue.dropped(), 2u);
}

TEST(SendQueue, ControlMessagesBeyondTheBoundAskToCloseTheConnection) {
  SendQueue queue(100);
  EXPECT_TRUE(queue.push(Frame::control(std::string(60, '{'))));
  EXPECT_FALSE(queue.push(Frame::control(std::string(60, '{'))));  // a client that asks and never reads
}

TEST(SendQueue, AStalledClientsQueueStaysBounded) {
  SendQueue queue(1000000);
  for (int i = 0; i < 10000; ++i) {
    queue.push(Frame::sample(1 + i % 3, 10, i, bytes(1000, 'x')));
    queue.push(Frame::time(i));
    queue.push(Frame::progress("{\"dropped\":" + std::to_string(i) + "}"));
    ASSERT_LE(queue.bytes(), 1000000u);
  }
  EXPECT_GT(queue.dropped(), 9000u);
  EXPECT_EQ(queue.pop()->kind, Frame::Kind::Progress);  // the newest count and time go first
  EXPECT_EQ(queue.pop()->kind, Frame::Kind::Time);
  int times = 1, progress = 1;
  while (auto frame = queue.pop()) {
    times += frame->kind == Frame::Kind::Time;
    progress += frame->kind == Frame::Kind::Progress;
  }
  EXPECT_EQ(times, 1);  // the newest time replaced the older ones
  EXPECT_EQ(progress, 1);
}
