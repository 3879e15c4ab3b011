#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "scanbus/topics.hpp"

namespace scanbus::cli {

void add_topics_command(CLI::App& app, int& exit_code) {
  auto* command = app.add_subcommand("topics", "List every topic: type, QoS, publishers, subscribers");
  static bool json = false;
  command->add_flag("--json", json, "One JSON object per topic");
  command->callback([&exit_code] {
    for (const auto& topic : topic_catalogue()) {
      if (json) {
        std::cout << nlohmann::json{{"name", topic.name},
                                    {"type", topic.type},
                                    {"qos", describe(topic.qos)},
                                    {"publishers", topic.publishers},
                                    {"subscribers", topic.subscribers},
                                    {"description", topic.description}}
                  << "\n";
      } else {
        std::printf("%-27s %-50s %s\n", topic.name.c_str(), topic.type.c_str(), describe(topic.qos).c_str());
      }
    }
    exit_code = 0;
  });
}

}  // namespace scanbus::cli
