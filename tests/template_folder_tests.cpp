// methods/_template, built into this test program only (no other program registers it): the
// folder a new method starts from passes the conformance suite.
#include "conformance.hpp"

#include "gl_test.hpp"

namespace vs::testing {
namespace {

class TemplateFolderTest : public GlTest {};

TEST_F(TemplateFolderTest, PassesTheConformanceSuite) {
  expectFolderAgrees("template", "methods/_template");
  expectLadderResolves("template");
  expectParametersReadAndEffective("template");
}

}  // namespace
}  // namespace vs::testing
