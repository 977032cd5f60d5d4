// Every method the harness can run: adding a method is its folder plus one line here.
#include "registry.hpp"

#include "dsm/dsm.hpp"
#include "ivsv/ivsv.hpp"
#include "minmax/minmax.hpp"
#include "raymarch/raymarch.hpp"
#include "slicemap/slicemap.hpp"
#include "vsv/vsv.hpp"

namespace vs {

template <typename T>
static MethodInfo entry() {
  return {T().name(), [] { return std::make_unique<T>(); }};
}

const MethodRegistry& registeredMethods() {
  static const MethodRegistry methods = {
      entry<RaymarchMethod>(),
      entry<MinmaxMethod>(),
      entry<VsvMethod>(),
      entry<DsmMethod>(),
      entry<SlicemapMethod>(),
      entry<IvsvMethod>(),
  };
  return methods;
}

}  // namespace vs
