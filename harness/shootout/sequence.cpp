#include "harness/shootout/sequence.hpp"

#include <algorithm>

#include "harness/io/results.hpp"

namespace vs::shootout {

SequenceMetrics sequenceMetrics(const std::vector<const Image*>& frames, const std::vector<const Image*>& references) {
  SequenceMetrics m;
  for (size_t k = 0; k < frames.size(); ++k) m.perFrame.push_back(compareImages(*frames[k], *references[k]));
  const std::vector<ErrorMetrics>& errors = m.perFrame;
  m.measured = !errors.empty();
  m.frames = int(errors.size());
  for (const ErrorMetrics& e : errors) {
    m.rmseMean += e.rmse / double(errors.size());
    m.relmseMean += e.relmse / double(errors.size());
    m.rmseMax = std::max(m.rmseMax, e.rmse);
    m.relmseMax = std::max(m.relmseMax, e.relmse);
  }
  m.temporal = temporalError(frames, references);
  return m;
}

const Image& FrameReferences::at(uint32_t index) {
  const double t = plan_.scene.animation.timeOf(index);
  auto it = byTime_.find(t);
  if (it != byTime_.end()) return it->second;
  if (t == plan_.scene.animation.timeOf(plan_.comparedFrame)) return byTime_[t] = base_.reference.inscatter;
  const std::string where = "frame " + std::to_string(index) + " (t = " + num(t) + " s)";
  if (plan_.exactReference) {
    progress_.note("ground truth of " + where);
    GroundTruth truth = obtainGroundTruth(sceneAt(plan_.scene, t), groundTruthOptions(req_, plan_, options_),
                                          cacheDirOf(req_), {});
    return byTime_[t] = std::move(truth.inscatter);
  }
  progress_.note("reference of " + where);
  Reference ref = obtainReference(sceneAt(plan_.scene, t), limits_, options_, base_.referenceShadowMap,
                                  cacheDirOf(req_), registry_, req_.referenceSpec);
  return byTime_[t] = std::move(ref.inscatter);
}

}  // namespace vs::shootout
