// Publishes PointCloud2 samples of N points (room_cloud.hpp) at a rate for a time, for bench/recording_throughput.sh.
//   recording_publisher POINTS RATE_HZ SECONDS [READERS]  (readers to wait for, default 1)
#include <iostream>
#include <thread>

#include "room_cloud.hpp"
#include "scanbus/service.hpp"
#include "scanbus/typed_topics.hpp"
#include "scanbus_msgs/PointCloud2PubSubTypes.h"

using namespace scanbus;

namespace {

sensor_msgs::msg::PointCloud2 room_cloud(uint32_t points, uint32_t seed) {
  sensor_msgs::msg::PointCloud2 cloud;
  cloud.header().frame_id("map");
  cloud.height(1);
  cloud.width(points);
  cloud.point_step(16);
  cloud.row_step(16 * points);
  cloud.is_dense(true);
  const char* names[] = {"x", "y", "z", "rgb"};
  for (uint32_t i = 0; i < 4; ++i) {
    sensor_msgs::msg::PointField field;
    field.name(names[i]);
    field.offset(4 * i);
    field.datatype(7);  // FLOAT32
    field.count(1);
    cloud.fields().push_back(field);
  }
  cloud.data(bench::room_cloud_points(points, seed));
  return cloud;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4 && argc != 5) {
    std::cerr << "usage: recording_publisher POINTS RATE_HZ SECONDS [READERS]\n";
    return 2;
  }
  const auto points = static_cast<uint32_t>(std::stoul(argv[1]));
  const double rate = std::stod(argv[2]), seconds = std::stod(argv[3]);
  const size_t readers = argc == 5 ? std::stoul(argv[4]) : 1;
  Participant participant(dds_settings_from_config(Config::parse("", "")), "recording_publisher");
  Writer<sensor_msgs::msg::PointCloud2PubSubType> writer(participant, topics::kScannerCloud);
  if (!writer.wait_for_readers(readers, std::chrono::seconds(20))) {
    std::cerr << "recording_publisher: fewer than " << readers << " readers on rt/scanner/cloud within 20 s\n";
    return 1;
  }
  // Two clouds alternate, so consecutive samples differ without generating each anew.
  const sensor_msgs::msg::PointCloud2 clouds[2] = {room_cloud(points, 1), room_cloud(points, 2)};
  const auto period = std::chrono::duration<double>(1.0 / rate);
  std::cerr << "publishing" << std::endl;  // the benchmark starts its clocks here
  const auto start = std::chrono::steady_clock::now();
  uint64_t published = 0;
  for (auto next = start; std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds);) {
    std::this_thread::sleep_until(next);
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    auto cloud = clouds[published % 2];
    cloud.header().stamp().sec(static_cast<int32_t>(published));
    if (writer.write(cloud)) ++published;
  }
  writer.wait_for_acknowledgments(std::chrono::seconds(30));
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  std::cout << "{\"published\": " << published << ", \"seconds\": " << elapsed.count() << "}\n";
  return 0;
}
