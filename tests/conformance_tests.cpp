// The conformance suite over every registered method: adding a method folder adds its rows.
#include "conformance.hpp"

#include "gl_test.hpp"

namespace vs::testing {
namespace {

class ConformanceTest : public GlTest, public ::testing::WithParamInterface<std::string> {};

std::vector<std::string> methodNames() {
  std::vector<std::string> names;
  for (const MethodInfo& info : registeredMethods()) names.push_back(info.name);
  return names;
}

TEST_P(ConformanceTest, FolderNameAndReadmeAgree) { expectFolderAgrees(GetParam(), "methods/" + GetParam()); }
TEST_P(ConformanceTest, EveryLadderRungResolves) { expectLadderResolves(GetParam()); }
TEST_P(ConformanceTest, EveryParameterIsReadAndChangesTheImage) { expectParametersReadAndEffective(GetParam()); }

INSTANTIATE_TEST_SUITE_P(Methods, ConformanceTest, ::testing::ValuesIn(methodNames()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace vs::testing
