// What every method folder promises, checked the same way for each registered method (and for
// the template): folder, name and README agree; every ladder rung resolves; every declared
// parameter is read and, within its range, changes the image (or is declared .sameImage() and
// does not).
#pragma once
#include <string>

namespace vs::testing {

// Adds a gtest failure per broken promise of method `name`, whose folder is `folder` (relative to
// the source root, e.g. "methods/vsv").
void expectFolderAgrees(const std::string& name, const std::string& folder);
void expectLadderResolves(const std::string& name);
void expectParametersReadAndEffective(const std::string& name);

}  // namespace vs::testing
