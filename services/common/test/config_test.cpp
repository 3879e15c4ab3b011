#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "scanbus/config.hpp"

using scanbus::Config;
using scanbus::ConfigError;

namespace {

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Config, ReadsTypedValuesWithDefaults) {
  const Config config = Config::parse("service:\n  health_period: 0.5\n  name: x\n  on: true\n", "t.yaml");
  const Config service = config.section("service");
  EXPECT_DOUBLE_EQ(service.number("health_period", 1.0, 0.0, 10.0), 0.5);
  EXPECT_EQ(service.text("name", ""), "x");
  EXPECT_TRUE(service.flag("on", false));
  EXPECT_EQ(service.integer("depth", 7, 0, 10), 7);
  EXPECT_NO_THROW(config.check_all_read());
}

TEST(Config, UnknownKeyIsNamedWithFile) {
  const Config config = Config::parse("service:\n  helth_period: 0.5\n", "svc.yaml");
  config.section("service").number("health_period", 1.0, 0.0, 10.0);
  EXPECT_EQ(error_of([&] { config.check_all_read(); }), "svc.yaml: unknown key 'service.helth_period'");
}

TEST(Config, UnknownTopLevelSectionIsReported) {
  const Config config = Config::parse("servce: {}\n", "svc.yaml");
  EXPECT_EQ(error_of([&] { config.check_all_read(); }), "svc.yaml: unknown key 'servce'");
}

TEST(Config, ASectionChecksOnlyItsOwnKeys) {
  // A command line tool reads one service's section of that service's file.
  const Config config = Config::parse("service: {health_period: 1}\nmatcher:\n  trim: 0.9\n  trm: 1\n", "m.yaml");
  const Config matcher = config.section("matcher");
  matcher.number("trim", 0.9, 0, 1);
  EXPECT_EQ(error_of([&] { matcher.check_all_read(); }), "m.yaml: unknown key 'matcher.trm'");
  matcher.number("trm", 0, 0, 1);
  EXPECT_NO_THROW(matcher.check_all_read());
}

TEST(Config, WrongTypeNamesKeyAndValue) {
  const Config config = Config::parse("service:\n  health_period: fast\n", "svc.yaml");
  EXPECT_EQ(error_of([&] { config.section("service").number("health_period", 1.0, 0.0, 10.0); }),
            "svc.yaml: key 'service.health_period' must be a number, got 'fast'");
}

TEST(Config, OutOfRangeIsAnError) {
  const Config config = Config::parse("depth: 100\n", "svc.yaml");
  EXPECT_EQ(error_of([&] { config.integer("depth", 1, 1, 10); }),
            "svc.yaml: key 'depth' must be between 1 and 10, got 100");
}

TEST(Config, NaNIsOutOfRange) {
  const Config config = Config::parse("x: .nan\n", "svc.yaml");
  EXPECT_NE(error_of([&] { config.number("x", 1.0, 0.0, 10.0); }), "");
}

TEST(Config, MapWhereValueExpected) {
  const Config config = Config::parse("x: {a: 1}\n", "svc.yaml");
  EXPECT_EQ(error_of([&] { config.number("x", 1.0, 0.0, 10.0); }),
            "svc.yaml: key 'x' must be a single value, got a map");
}

TEST(Config, ChoiceListsAllowedValues) {
  const Config config = Config::parse("mode: fastest\n", "svc.yaml");
  EXPECT_EQ(error_of([&] {
              config.choice("mode", "a", {"a", "b"});
            }),
            "svc.yaml: key 'mode' must be one of a, b, got 'fastest'");
}

TEST(Config, MissingFileIsAnError) {
  EXPECT_EQ(error_of([] { Config::load("/nonexistent/scanbus.yaml"); }),
            "/nonexistent/scanbus.yaml: cannot open config file");
}

TEST(Config, SyntaxErrorNamesLine) {
  const std::string message = error_of([] { Config::parse("a: 1\nb: [1, 2\n", "bad.yaml"); });
  EXPECT_NE(message.find("bad.yaml: invalid YAML at line"), std::string::npos) << message;
}

TEST(Config, TopLevelMustBeAMap) {
  EXPECT_EQ(error_of([] { Config::parse("- 1\n- 2\n", "list.yaml"); }), "list.yaml: top level must be a map of keys");
}

TEST(Config, EmptyFileMeansDefaults) {
  const Config config = Config::parse("", "empty.yaml");
  EXPECT_EQ(config.section("service").text("name", "d"), "d");
  EXPECT_NO_THROW(config.check_all_read());
}

TEST(Config, LoadsFromFile) {
  const std::string path = ::testing::TempDir() + "/scanbus_config_test.yaml";
  std::ofstream(path) << "a: 3\n";
  EXPECT_EQ(Config::load(path).integer("a", 0, 0, 5), 3);
  std::remove(path.c_str());
}

TEST(Config, ListsOfNumbersAndMaps) {
  const Config config = Config::parse(
      "corners: [[0, 0], [5, 0], [5, 3]]\norigin: [1, 2, 3]\nboxes:\n  - {min: [0, 0, 0], max: [1, 1, 1]}\n",
      "room.yaml");
  EXPECT_EQ(config.number_rows("corners", 2).size(), 3u);
  EXPECT_EQ(config.numbers("origin", 3)[2], 3.0);
  const auto boxes = config.maps("boxes");
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].numbers("max", 3)[0], 1.0);
  EXPECT_EQ(boxes[0].numbers("min", 3)[0], 0.0);
  EXPECT_NO_THROW(config.check_all_read());
}

TEST(Config, UnknownKeyInsideAListIsNamed) {
  const Config config = Config::parse("boxes:\n  - {min: [0, 0, 0], max: [1, 1, 1], colour: red}\n", "room.yaml");
  for (const auto& box : config.maps("boxes")) box.numbers("min", 3), box.numbers("max", 3);
  EXPECT_EQ(error_of([&] { config.check_all_read(); }), "room.yaml: unknown key 'boxes[0].colour'");
}

TEST(Config, BadRowsAreNamed) {
  const Config config = Config::parse("corners: [[0, 0], [5]]\norigin: [1, x, 3]\n", "room.yaml");
  EXPECT_EQ(error_of([&] { config.number_rows("corners", 2); }),
            "room.yaml: key 'corners[1]' must be a list of 2 numbers, got a list");
  EXPECT_EQ(error_of([&] { config.numbers("origin", 3); }), "room.yaml: key 'origin' must hold numbers, got 'x'");
  EXPECT_EQ(error_of([&] { config.numbers("nothing", 3); }), "room.yaml: key 'nothing' is required");
}

// Eight levels of ten aliases: 546 bytes that expand to 10^8 values. Before the bound every
// walk over it ran for minutes (ctest's timeout fails this test if that comes back).
TEST(Config, AliasesExpandingPastTheBoundAreRefused) {
  std::string yaml = "l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level <= 8; ++level) {
    const std::string below = "*l" + std::to_string(level - 1);
    yaml += "l" + std::to_string(level) + ": &l" + std::to_string(level) + " [";
    for (int i = 0; i < 10; ++i) yaml += (i ? ", " : "") + below;
    yaml += "]\n";
  }
  const std::string message = error_of([&] { Config::parse(yaml, "bomb.yaml"); });
  EXPECT_NE(message.find("bomb.yaml: more than 100000 values once its aliases are expanded"), std::string::npos)
      << message;
}

TEST(Config, AliasesWithinTheBoundAreFine) {
  const Config config = Config::parse("base: &b [1, 2, 3]\ncopy: *b\n", "alias.yaml");
  EXPECT_EQ(config.numbers("copy", 3)[2], 3.0);
}

TEST(Config, NestingPastTheBoundIsRefused) {
  const std::string yaml = "a: " + std::string(100, '[') + std::string(100, ']') + "\n";
  const std::string message = error_of([&] { Config::parse(yaml, "deep.yaml"); });
  EXPECT_NE(message.find("deep.yaml: line 1: nested deeper than 64 levels"), std::string::npos) << message;
}

TEST(Config, AFileLargerThanAConfigIsRefused) {
  const std::string path = ::testing::TempDir() + "/scanbus_config_large.yaml";
  {
    std::ofstream out(path);
    out << "a: 1\n";
    for (int i = 0; i < 70000; ++i) out << "# a comment line of some length\n";
  }
  EXPECT_EQ(error_of([&] { Config::load(path); }), path + ": larger than 1 MiB; refused (not a config?)");
  std::remove(path.c_str());
}
