// Every bad input the suite tries, with the fixture files they need. Shared by the CLI tests and
// the stability report (which lists what the user sees for each).
#pragma once
#include <ostream>
#include <string>
#include <vector>

namespace vs::testing {

struct BadInput {
  std::string name;
  std::vector<std::string> args;  // "%DIR%" stands for the fixture folder
  std::string expectInError;      // text the one error line must contain
  std::string what;               // one line for the README table
};

inline void PrintTo(const BadInput& b, std::ostream* os) { *os << b.name; }

const std::vector<BadInput>& badInputs();
void writeBadInputFixtures(const std::string& dir);
std::vector<std::string> badInputArgs(const BadInput& bad, const std::string& dir);

}  // namespace vs::testing
