// Measures a room from a PCD, PLY or XYZ file in metres (scanner at the origin) with the
// installed scanbus libraries and the thesis's default settings.
#include <cstdio>
#include <exception>

#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/room_measurement/room_measurement.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CLOUD_FILE\n", argv[0]);
    return 2;
  }
  try {
    const auto points = scanbus::cloud_io::read_cloud(argv[1], 1.0);
    const auto room = scanbus::room_measurement::measure_room(points, {});
    std::printf("status %s: %s\n", scanbus::room_measurement::status_name(room.status), room.message.c_str());
    for (size_t i = 0; i < room.walls.size(); ++i)
      std::printf("wall %zu: %.3f m +- %.3f\n", i + 1, room.walls[i].length, room.walls[i].length_sigma);
    std::printf("area %.4f m2 +- %.4f\n", room.area, room.area_sigma);
    return room.status == scanbus::room_measurement::RoomStatus::Ok ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 2;
  }
}
