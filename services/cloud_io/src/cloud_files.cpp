#include "scanbus/cloud_io/cloud_files.hpp"

#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace scanbus::cloud_io {

namespace {

std::string extension_of(const std::string& path) {
  const size_t dot = path.rfind('.');
  std::string extension = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  return extension;
}

std::vector<Eigen::Vector3f> read_xyz(const std::string& path) {
  std::ifstream in(path);
  std::vector<Eigen::Vector3f> points;
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    // strtof, unlike >>, reads "nan" and "inf": such points are counted, then dropped.
    const char* at = line.c_str();
    float xyz[3];
    for (float& value : xyz) {
      char* end = nullptr;
      value = std::strtof(at, &end);
      if (end == at)
        throw CloudFileError(path + ":" + std::to_string(number) + ": expected three numbers x y z, got '" +
                             line.substr(0, 60) + "'");
      at = end;
    }
    points.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  return points;
}

// A point or element count in a PCD or PLY header: decimal digits, at most 2^32.
std::optional<unsigned long long> header_count(const std::string& text) {
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || text[0] == '-' || value > (1ull << 32)) return std::nullopt;
  return value;
}

unsigned long long file_size(const std::string& path) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  return error ? 0 : size;
}

// binary_compressed data starts with its compressed and uncompressed sizes (little endian
// uint32), and PCL trusts both: it resizes its buffer to the uncompressed size, then copies
// POINTS x fields out of it, and reads as many compressed bytes as the first says, past the
// file's end if need be (found by tests/fuzz, cloud_file). So both must fit the header.
template <typename Fail>
void check_compressed_sizes(std::istream& data, unsigned long long left, unsigned long long expected,
                            const Fail& fail) {
  unsigned char sizes[8];
  if (left < 8 || !data.read(reinterpret_cast<char*>(sizes), 8)) fail("binary_compressed data without its sizes");
  const auto uint32_at = [&](int at) {
    return static_cast<unsigned long long>(sizes[at]) | sizes[at + 1] << 8 | sizes[at + 2] << 16 |
           static_cast<unsigned long long>(sizes[at + 3]) << 24;
  };
  if (uint32_at(0) > left - 8)
    fail("compressed size " + std::to_string(uint32_at(0)) + " past the file's " + std::to_string(left - 8) +
         " bytes of data");
  if (uint32_at(4) != expected)
    fail("uncompressed size " + std::to_string(uint32_at(4)) + " is not the " + std::to_string(expected) +
         " bytes POINTS x fields take");
}

// PCL's header reader goes on after DATA: it skips empty and comment lines and applies any
// line that starts like a key (FIELDSX counts as FIELDS) to the cloud it then fills with the
// data, as the first DATA line said. Data that starts so is refused (a second FIELDS, SIZE,
// TYPE... made PCL read past its buffer: found by tests/fuzz, cloud_file).
template <typename Fail>
void check_no_header_after_data(const std::string& path, std::streamoff data_start, const Fail& fail) {
  static const char* kPclKeys[] = {"FIELDS", "COLUMNS", "SIZE",      "TYPE",   "COUNT",
                                   "WIDTH",  "HEIGHT",  "VIEWPOINT", "POINTS", "DATA"};
  std::ifstream in(path, std::ios::binary);
  in.seekg(data_start);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    std::istringstream words(line);
    std::string key;
    if (!(words >> key)) return;
    if (key[0] == '#' || key.rfind("VERSION", 0) == 0) continue;
    for (const char* pcl_key : kPclKeys)
      if (key.rfind(pcl_key, 0) == 0) fail("the data starts with a header line, " + key.substr(0, 20));
    return;
  }
}

// PCL's PCD reader crashes on damaged headers (a DATA line without FIELDS, found by
// tests/fuzz, cloud_file): check the whole header first, so PCL reads only what is a
// consistent PCD header: known keys, one SIZE, TYPE (and COUNT) per field, types I or U of
// 1, 2, 4 or 8 bytes, F of 4 or 8, B of 1, POINTS = WIDTH x HEIGHT, DATA ascii, binary or binary_compressed.
void check_pcd_header(const std::string& path) {
  static const char* kKeys[] = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  const auto fail = [&](const std::string& why) {
    throw CloudFileError(path + ": not a readable pcd file (" + why + ")");
  };
  std::map<std::string, std::vector<std::string>> header;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int number = 1; number <= 32 && std::getline(in, line); ++number) {
    if (line.size() > 4096 || std::any_of(line.begin(), line.end(), [](char c) {
          return static_cast<unsigned char>(c) < 0x09 || static_cast<unsigned char>(c) > 0x7e;
        }))
      fail("binary bytes in the header, line " + std::to_string(number));
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string key, word;
    words >> key;
    if (std::none_of(std::begin(kKeys), std::end(kKeys), [&](const char* k) { return key == k; }))
      fail("unknown header key '" + key.substr(0, 20) + "'");
    if (header.count(key)) fail("header key " + key + " twice");
    auto& values = header[key];
    while (words >> word) values.push_back(word);
    if (key == "DATA") break;
  }
  for (const char* key : {"FIELDS", "SIZE", "TYPE", "WIDTH", "POINTS", "DATA"})
    if (!header.count(key) || header[key].empty()) fail(std::string("no ") + key + " line in the header");
  const size_t fields = header["FIELDS"].size();
  for (const char* key : {"SIZE", "TYPE", "COUNT"})
    if (header.count(key) && header[key].size() != fields)
      fail(std::string(key) + " does not give one value per field");
  // The types PCL knows (pcl::getFieldType): with any other, its reader indexes by type 255.
  for (size_t f = 0; f < fields; ++f) {
    const std::string &size = header["SIZE"][f], &type = header["TYPE"][f];
    const bool integer = (type == "I" || type == "U") && (size == "1" || size == "2" || size == "4" || size == "8");
    if (!integer && !(type == "F" && (size == "4" || size == "8")) && !(type == "B" && size == "1"))
      fail("field type '" + type.substr(0, 20) + "' of size '" + size.substr(0, 20) + "'");
  }
  const auto count = [&](const std::string& key, const std::string& fallback) {
    const std::string text = header.count(key) && !header[key].empty() ? header[key][0] : fallback;
    const auto value = header_count(text);
    if (!value) fail(key + " '" + text.substr(0, 20) + "'");
    return *value;
  };
  for (const auto& value : header.count("COUNT") ? header["COUNT"] : std::vector<std::string>{})
    if (value.find_first_not_of("0123456789") != std::string::npos || value.empty() || value.size() > 6 || value == "0")
      fail("field count '" + value.substr(0, 20) + "'");
  const unsigned long long points = count("POINTS", "");
  if (points != count("WIDTH", "") * count("HEIGHT", "1")) fail("POINTS is not WIDTH x HEIGHT");
  const std::string& data = header["DATA"][0];
  if (data != "ascii" && data != "binary" && data != "binary_compressed") fail("DATA '" + data.substr(0, 20) + "'");
  // PCL sizes its buffers by POINTS: no more than the file can hold (LZF packs at most
  // about 100 to 1), so a damaged count is an error rather than gigabytes allocated.
  unsigned long long point_bytes = 0;
  for (size_t f = 0; f < fields; ++f)
    point_bytes += std::stoull(header["SIZE"][f]) * (header.count("COUNT") ? std::stoull(header["COUNT"][f]) : 1);
  // A DATA line that ends the file leaves the stream at its end, where tellg says -1.
  const std::streamoff data_start = in.good() ? std::streamoff(in.tellg()) : std::streamoff(file_size(path));
  const unsigned long long left = file_size(path) - static_cast<unsigned long long>(data_start);
  const unsigned long long per_point = data == "ascii" ? 2 * fields : point_bytes;
  if (points * per_point > (data == "binary_compressed" ? 100 : 1) * left)
    fail("POINTS " + std::to_string(points) + " do not fit in the file's " + std::to_string(left) + " bytes of data");
  if (data == "binary_compressed") check_compressed_sizes(in, left, points * point_bytes, fail);
  check_no_header_after_data(path, data_start, fail);
}

// PCL's PLY reader sizes its buffers by the header's element counts before reading
// ("element vertex -1" is 4 billion vertices; found by tests/fuzz, cloud_file): check that
// every element's count fits in the file (at least one byte and a separator per ascii
// value, the values' sizes in binary).
void check_ply_header(const std::string& path) {
  const auto fail = [&](const std::string& why) {
    throw CloudFileError(path + ": not a readable ply file (" + why + ")");
  };
  static const std::map<std::string, unsigned> kSizes = {{"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},
                                                         {"short", 2}, {"ushort", 2},  {"int16", 2},  {"uint16", 2},
                                                         {"int", 4},   {"uint", 4},    {"int32", 4},  {"uint32", 4},
                                                         {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  std::ifstream in(path, std::ios::binary);
  std::string line, format;
  std::vector<std::pair<unsigned long long, unsigned long long>> elements;  // count, minimum bytes of one
  for (int number = 1; std::getline(in, line); ++number) {
    if (number > 1000 || line.size() > 4096) fail("no end_header in the first 1000 lines");
    std::istringstream words(line);
    std::string key, type;
    words >> key;
    if (number == 1 && key != "ply") fail("no 'ply' line first");
    if (key == "format") words >> format;
    if (key == "element") {
      std::string name, text;
      words >> name >> text;
      const auto count = header_count(text);
      if (!count) fail("element " + name.substr(0, 20) + " count '" + text.substr(0, 20) + "'");
      elements.emplace_back(*count, 0);
    }
    if (key == "property") {
      if (elements.empty()) fail("a property before any element");
      words >> type;
      if (type == "list") words >> type;  // the list's count type: the least such a value takes
      const auto size = kSizes.find(type);
      if (size == kSizes.end()) fail("property type '" + type.substr(0, 20) + "'");
      elements.back().second += format == "ascii" ? 2 : size->second;
    }
    if (key == "end_header") {
      unsigned long long needed = 0;
      for (const auto& [count, bytes] : elements) needed += count * bytes;
      const unsigned long long left =
          file_size(path) - static_cast<unsigned long long>(std::max<std::streamoff>(in.tellg(), 0));
      if (needed > left)
        fail("its elements need " + std::to_string(needed) + " bytes, the file holds " + std::to_string(left));
      return;
    }
  }
  fail("no end_header");
}

// x, y and z of every point PCL's reader filled in, each checked against the bytes first:
// PCL's own conversion trusts the header's point count and reads past the data of a file
// cut short (found by tests/fuzz, cloud_file).
std::vector<Eigen::Vector3f> xyz_of(const pcl::PCLPointCloud2& cloud, const std::string& path) {
  struct Field {
    size_t offset;
    bool is_double;
  };
  Field fields[3];
  for (int axis = 0; axis < 3; ++axis) {
    const std::string name(1, "xyz"[axis]);
    const auto found =
        std::find_if(cloud.fields.begin(), cloud.fields.end(), [&](const auto& f) { return f.name == name; });
    if (found == cloud.fields.end()) throw CloudFileError(path + ": no field '" + name + "'");
    const bool is_double = found->datatype == pcl::PCLPointField::FLOAT64;
    if (!is_double && found->datatype != pcl::PCLPointField::FLOAT32)
      throw CloudFileError(path + ": field '" + name + "' is not a 32 or 64 bit float");
    if (static_cast<uint64_t>(found->offset) + (is_double ? 8 : 4) > cloud.point_step)
      throw CloudFileError(path + ": field '" + name + "' lies outside the point's " +
                           std::to_string(cloud.point_step) + " bytes");
    fields[axis] = {found->offset, is_double};
  }
  const uint64_t row = static_cast<uint64_t>(cloud.width) * cloud.point_step;
  const uint64_t needed = cloud.height == 0 ? 0 : (static_cast<uint64_t>(cloud.height) - 1) * cloud.row_step + row;
  if (cloud.row_step < row || needed > cloud.data.size())
    throw CloudFileError(
        path + ": the header promises " + std::to_string(static_cast<uint64_t>(cloud.width) * cloud.height) +
        " points, the data holds " + std::to_string(cloud.point_step ? cloud.data.size() / cloud.point_step : 0));
  std::vector<Eigen::Vector3f> points;
  points.reserve(static_cast<size_t>(cloud.width) * cloud.height);
  for (uint32_t r = 0; r < cloud.height; ++r) {
    for (uint32_t c = 0; c < cloud.width; ++c) {
      const uint8_t* point =
          cloud.data.data() + static_cast<size_t>(r) * cloud.row_step + static_cast<size_t>(c) * cloud.point_step;
      Eigen::Vector3f xyz;
      for (int axis = 0; axis < 3; ++axis) {
        if (fields[axis].is_double) {
          double value;
          std::memcpy(&value, point + fields[axis].offset, sizeof value);
          xyz[axis] = static_cast<float>(value);
        } else {
          std::memcpy(&xyz[axis], point + fields[axis].offset, sizeof(float));
        }
      }
      points.push_back(xyz);
    }
  }
  return points;
}

}  // namespace

std::vector<Eigen::Vector3f> read_cloud(const std::string& path, double scale) {
  if (!std::ifstream(path)) throw CloudFileError(path + ": cannot open");
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // our one line says what is wrong
  const std::string extension = extension_of(path);
  std::vector<Eigen::Vector3f> points;
  if (extension == "xyz" || extension == "txt") {
    points = read_xyz(path);
  } else if (extension == "pcd" || extension == "ply") {
    if (extension == "pcd") check_pcd_header(path);
    if (extension == "ply") check_ply_header(path);
    pcl::PCLPointCloud2 cloud;
    int status = -1;
    try {
      pcl::PLYReader ply;
      status = extension == "pcd" ? pcl::io::loadPCDFile(path, cloud) : ply.read(path, cloud);
    } catch (const std::exception& e) {  // PCL throws on some damage and returns -1 on other
      throw CloudFileError(path + ": not a readable " + extension + " file: " + e.what());
    }
    if (status < 0) throw CloudFileError(path + ": not a readable " + extension + " file");
    points = xyz_of(cloud, path);
  } else {
    throw CloudFileError(path + ": unknown format '." + extension + "' (pcd, ply, xyz)");
  }
  if (points.empty()) throw CloudFileError(path + ": no points");
  if (scale != 1.0)
    for (auto& p : points) p *= static_cast<float>(scale);
  return points;
}

void write_pcd(const std::string& path, const std::vector<CloudPoint>& points) {
  pcl::PointCloud<pcl::PointXYZI> cloud;
  for (const auto& point : points) {
    pcl::PointXYZI out;
    out.x = point.position.x();
    out.y = point.position.y();
    out.z = point.position.z();
    out.intensity = point.intensity;
    cloud.push_back(out);  // keeps width x height == size, which the writer checks
  }
  if (cloud.empty() || pcl::io::savePCDFileBinary(path, cloud) != 0)
    throw std::runtime_error(path + ": cannot write PCD" + (cloud.empty() ? " (no points)" : ""));
}

double metres_per_unit(const std::string& unit) {
  if (unit == "mm") return 0.001;
  if (unit == "cm") return 0.01;
  if (unit == "m") return 1.0;
  throw std::invalid_argument("unknown unit '" + unit + "' (m, cm or mm)");
}

}  // namespace scanbus::cloud_io
