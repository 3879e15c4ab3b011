#include <gtest/gtest.h>

#include <algorithm>

#include "scanbus/permissions.hpp"

using scanbus::Grant;

namespace {

bool has(const std::vector<std::string>& topics, const std::string& topic) {
  return std::find(topics.begin(), topics.end(), topic) != topics.end();
}

}  // namespace

TEST(Permissions, EachServiceGetsExactlyItsCatalogueTopics) {
  const auto grants = scanbus::catalogue_grants({"scanner_io", "pose_estimation", "recorder"});
  ASSERT_EQ(grants.size(), 4u);
  const Grant& scanner = grants[0];
  EXPECT_EQ(scanner.identity, "scanner_io");
  EXPECT_EQ(scanner.publish, (std::vector<std::string>{"rt/scanbus/health", "rt/scanner/status", "rt/scanner/spherical",
                                                       "rt/scanner/cloud", "rt/scanner/scan_cloud"}));
  EXPECT_EQ(scanner.subscribe, std::vector<std::string>{"rt/scanner/command"});
  const Grant& pose = grants[1];
  EXPECT_TRUE(has(pose.subscribe, "rt/scan"));  // its ground clearance
  EXPECT_TRUE(has(pose.publish, "rt/tf_static"));
  EXPECT_FALSE(has(pose.publish, "rt/room/measurement"));
  EXPECT_FALSE(has(pose.subscribe, "rt/scanner/command"));
  EXPECT_EQ(grants[2].subscribe, std::vector<std::string>{"*"});  // the recorder records any topic
  EXPECT_EQ(grants[2].publish, std::vector<std::string>{"rt/scanbus/health"});
  EXPECT_EQ(grants[3].identity, "operator");
}

TEST(Permissions, TheDocumentNamesEachSubjectAndDeniesTheRest) {
  const std::string xml = scanbus::permissions_document(scanbus::catalogue_grants({"room_measurement"}),
                                                        "2020-01-01T00:00:00", "2040-01-01T00:00:00");
  EXPECT_NE(xml.find("<subject_name>CN=room_measurement,O=scanbus</subject_name>"), std::string::npos);
  EXPECT_NE(xml.find("<publish><topics><topic>rt/scanbus/health</topic><topic>rt/room/measurement</topic>"
                     "<topic>rt/room/walls</topic></topics></publish>"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("<subscribe><topics><topic>rt/scanner/scan_cloud</topic></topics></subscribe>"),
            std::string::npos);
  EXPECT_NE(xml.find("<subject_name>CN=operator,O=scanbus</subject_name>"), std::string::npos);
  EXPECT_EQ(std::count(xml.begin(), xml.end(), '\n') > 10, true);
  size_t denies = 0;
  for (size_t at = xml.find("<default>DENY</default>"); at != std::string::npos;
       at = xml.find("<default>DENY</default>", at + 1))
    ++denies;
  EXPECT_EQ(denies, 2u);
}
