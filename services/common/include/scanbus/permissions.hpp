// DDS Security permissions from the topic catalogue: one identity per service, allowed to
// publish and subscribe exactly the topics the catalogue says it writes and reads (its
// publishers and subscribers columns), plus its Health. Two identities are wider by what
// they are: `recorder` reads every topic (it records whatever it is asked to), `operator`
// (the command line tools: echo, health, replay, record, demo) writes and reads every topic.
// scripts/make-security.sh signs what permissions_document() writes.
#pragma once

#include <string>
#include <vector>

namespace scanbus {

struct Grant {
  std::string identity;                         // the certificate's CN
  std::vector<std::string> publish, subscribe;  // DDS topic names, or "*"
};

// One grant per service named, then the operator's.
std::vector<Grant> catalogue_grants(const std::vector<std::string>& services);

// The permissions XML (OMG DDS Security 1.1) of the grants, subject "CN=identity,O=scanbus",
// valid from not_before to not_after (UTC, e.g. "2020-01-01T00:00:00"), on domains 0-232.
std::string permissions_document(const std::vector<Grant>& grants, const std::string& not_before,
                                 const std::string& not_after);

}  // namespace scanbus
