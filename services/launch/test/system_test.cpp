// launch::System with small programs in place of services: what it writes, what the children
// see, and what it says when one of them fails.
#include "scanbus/launch/system.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <iterator>

#include "scanbus/config.hpp"
#include "scanbus/topics.hpp"

using namespace scanbus;
using namespace scanbus::launch;

namespace {

class SystemTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char dir[] = "/tmp/scanbus_launch_XXXXXX";
    work_ = mkdtemp(dir);
  }
  void TearDown() override { std::system(("rm -rf " + work_).c_str()); }

  std::string read(const std::string& file) const {
    std::ifstream in(work_ + "/" + file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  // `executable` stands in for the scanbus command.
  SystemSettings settings(const std::string& executable = "/bin/echo") const {
    return {executable, work_, DdsSettings{"", "localhost", 42}};
  }

  std::string work_;
};

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

}  // namespace

// What a service reads back (with its own Config checks) is what was set.
TEST_F(SystemTest, AServiceReadsTheConfigItWasGiven) {
  ServiceConfig config;
  config.health_period = 0.25;
  config.log_level = "warn";
  config.qos["rt/scan"] = QosSettings{true, true, false, 1000};
  config.settings["port"] = "/dev/ttyACM0";
  config.settings["matcher"]["opening"] = 170.5;
  config.settings["origin"] = std::vector<double>{47.123456789012, 8.5, 420.25};

  const Config file = Config::parse(config.to_yaml("scan_matcher"), "test");
  EXPECT_DOUBLE_EQ(file.section("service").number("health_period", 1, 0, 60), 0.25);
  EXPECT_EQ(file.section("service").text("log_level", ""), "warn");
  const QosSettings qos = qos_from_config(file.section("qos"), topic_info("rt/scan"));
  EXPECT_TRUE(qos.reliable);
  EXPECT_TRUE(qos.transient_local);
  EXPECT_FALSE(qos.keep_all);
  EXPECT_EQ(qos.depth, 1000);
  const Config section = file.section("scan_matcher");
  EXPECT_EQ(section.text("port", ""), "/dev/ttyACM0");
  EXPECT_DOUBLE_EQ(section.section("matcher").number("opening", 0, 0, 360), 170.5);
  EXPECT_EQ(section.numbers("origin", 3), (std::vector<double>{47.123456789012, 8.5, 420.25}));
  EXPECT_NO_THROW(file.check_all_read());
}

TEST_F(SystemTest, ACopiedConfigIsItsOwn) {
  ServiceConfig common;
  common.qos["rt/pose"] = QosSettings{true, false, false, 1000};
  ServiceConfig matcher = common, assembly = common;
  matcher.settings["opening"] = 90;
  assembly = common;
  assembly.settings["transform_timeout"] = 30;
  EXPECT_FALSE(common.settings["opening"].IsDefined() || common.settings["transform_timeout"].IsDefined());
  EXPECT_FALSE(assembly.settings["opening"].IsDefined());
  EXPECT_FALSE(matcher.settings["transform_timeout"].IsDefined());
  EXPECT_EQ(assembly.qos.size(), 1u);
  ServiceConfig moved = std::move(matcher);  // a copy: yaml-cpp's node has no move of its own
  matcher.settings["max_correspondence"] = 0.15;
  EXPECT_FALSE(moved.settings["max_correspondence"].IsDefined());
}

TEST_F(SystemTest, AnEmptyConfigSaysNothing) { EXPECT_EQ(ServiceConfig{}.to_yaml("scanner_io"), "{}\n"); }

// `scanbus run <service> --config <file>`, the file written first, the output in <service>.log.
TEST_F(SystemTest, StartsAServiceWithItsConfigFile) {
  System system(settings());
  ServiceConfig config;
  config.settings["scans"] = 3;
  ChildProcess& echo = system.start("room_measurement", config, Lifetime::RunsToEnd);
  ASSERT_TRUE(system.wait_for([&] { return echo.exited().has_value(); }, 10));
  EXPECT_EQ(read("room_measurement.log"), "run room_measurement --config " + work_ + "/room_measurement.yaml\n");
  EXPECT_EQ(Config::load(work_ + "/room_measurement.yaml").section("room_measurement").integer("scans", 0, 0, 9), 3);
}

TEST_F(SystemTest, ChildrenJoinTheSystemsDomainAndProfile) {
  setenv("SCANBUS_DDS_PROFILE_FILE", "/somewhere/else.xml", 1);  // ours, not theirs
  System system(settings());
  ChildProcess& shell = system.start_program(
      "env", "/bin/sh", {"-c", "echo $SCANBUS_DOMAIN_ID $SCANBUS_DDS_PROFILE [$SCANBUS_DDS_PROFILE_FILE]"},
      Lifetime::RunsToEnd);
  ASSERT_TRUE(system.wait_for([&] { return shell.exited().has_value(); }, 10));
  EXPECT_EQ(read("env.log"), "42 localhost []\n");
  unsetenv("SCANBUS_DDS_PROFILE_FILE");
}

TEST_F(SystemTest, AServiceThatEndsIsNamedWithItsLog) {
  System system(settings("/bin/false"));
  system.start("scanner_io");
  const std::string error =
      error_of([&] { system.wait_until([] { return false; }, 10, "the services did not appear on DDS"); });
  EXPECT_NE(error.find("false run"), std::string::npos) << error;
  EXPECT_NE(error.find("status 1"), std::string::npos) << error;
  EXPECT_NE(error.find(work_ + "/scanner_io.log"), std::string::npos) << error;
}

TEST_F(SystemTest, AJobThatRunsToItsEndFailsOnlyWithAStatus) {
  System system(settings());
  ChildProcess& done = system.start_program("done", "/bin/sh", {"-c", "exit 0"}, Lifetime::RunsToEnd);
  EXPECT_TRUE(system.wait_for([&] { return done.exited().has_value(); }, 10));
  EXPECT_NO_THROW(system.check());
  system.start_program("failed", "/bin/sh", {"-c", "exit 3"}, Lifetime::RunsToEnd);
  const std::string error = error_of([&] { system.wait_for([] { return false; }, 10); });
  EXPECT_NE(error.find("exited with status 3"), std::string::npos) << error;
  EXPECT_NE(error.find(work_ + "/failed.log"), std::string::npos) << error;
}

TEST_F(SystemTest, WaitingTooLongNamesWhatDidNotHappen) {
  System system(settings());
  system.start_program("sleeper", "/bin/sleep", {"30"});
  EXPECT_EQ(error_of([&] { system.wait_until([] { return false; }, 0.1, "no complete scan"); }),
            "no complete scan within 0.1 s");
  EXPECT_FALSE(system.wait_for([] { return false; }, 0.05));
}

TEST_F(SystemTest, ANameStartsOnce) {
  System system(settings());
  system.start("scanner_io", {}, Lifetime::RunsToEnd);
  EXPECT_THROW(system.start("scanner_io"), std::invalid_argument);
  EXPECT_THROW(system.start_program("scanner_io", "/bin/true", {}), std::invalid_argument);
}

TEST_F(SystemTest, ATemporaryWorkFolderGoesWithTheSystem) {
  const std::string folder = work_ + "/run";
  {
    SystemSettings temporary = settings();
    temporary.work_dir = folder;
    temporary.temporary = true;
    System system(temporary);
    system.start_program("sleeper", "/bin/sleep", {"30"});
    EXPECT_EQ(access(folder.c_str(), F_OK), 0);
  }
  EXPECT_NE(access(folder.c_str(), F_OK), 0);
}

// The children end with the System (and one earlier when asked), without waiting out a sleep.
TEST_F(SystemTest, StopsItsChildren) {
  const auto start = std::chrono::steady_clock::now();
  {
    System system(settings());
    ChildProcess& first = system.start_program("first", "/bin/sleep", {"30"});
    system.start_program("second", "/bin/sleep", {"30"});
    system.stop(first);
    EXPECT_NO_THROW(system.check());  // the stopped one is no longer watched
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}
