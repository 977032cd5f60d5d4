// The project's methods: each registers itself from its own folder (VS_REGISTER_METHOD in its
// .cpp), so adding a method edits no list here.
#include "registry.hpp"

#include <algorithm>
#include <stdexcept>

namespace vs {
namespace {

struct Registered {
  int position;
  MethodInfo info;
};

// Filled during static initialisation, before main; kept in listing order as entries arrive, so
// it is complete and sorted whenever anything reads it.
std::vector<Registered>& registrations() {
  static std::vector<Registered> entries;
  return entries;
}

MethodRegistry& registry() {
  static MethodRegistry methods;
  return methods;
}

}  // namespace

MethodRegistration::MethodRegistration(int position, std::function<std::unique_ptr<Method>()> create) {
  std::string name = create()->name();
  auto& entries = registrations();
  for (const Registered& r : entries)
    if (r.info.name == name) throw std::logic_error("method '" + name + "' is registered twice");
  auto at = std::upper_bound(entries.begin(), entries.end(), position,
                             [](int p, const Registered& r) { return p < r.position; });
  entries.insert(at, Registered{position, MethodInfo{std::move(name), std::move(create)}});
  MethodRegistry& methods = registry();
  methods.clear();
  for (const Registered& r : entries) methods.push_back(r.info);
}

const MethodRegistry& registeredMethods() { return registry(); }

}  // namespace vs
