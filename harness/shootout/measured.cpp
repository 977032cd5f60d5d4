#include "harness/shootout/measured.hpp"

namespace vs::shootout {

Measured measureJob(Runner& runner, const Job& job, const MethodRegistry& registry, const RunPlan& plan,
                    const Baselines& base, Progress& progress) {
  Measured m;
  auto method = createMethod(registry, job.method);
  m.run = runner.run(*method, job.params, [&](int done, int total) { progress.frames(done, total); });
  bool ok = m.run.status == RunStatus::Success;
  m.measured = plan.haveReference && ok;
  m.exactMeasured = plan.haveExact && ok;
  if (m.measured) {
    m.finalErr = compareImages(m.run.final, base.reference.final);
    m.lsErr = compareImages(m.run.inscatter, base.reference.inscatter);
  }
  if (m.exactMeasured) {
    m.exactErr = compareImages(m.run.final, base.exact.final);
    m.exactLsErr = compareImages(m.run.inscatter, base.exact.inscatter);
  }
  return m;
}

}  // namespace vs::shootout
