#include "harness/gl/work_counters.hpp"

#include <algorithm>

#include "harness/pipeline/frame.hpp"

namespace vs {

WorkCounters::WorkCounters(std::vector<std::string> names) : names_(std::move(names)) {}

void WorkCounters::begin(int width, int height) {
  if (!counters_ || width != width_ || height != height_) {
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
    glTextureStorage3D(id, 1, GL_R32UI, width, height, GLsizei(names_.size()));
    counters_ = gl::Texture(id);
    width_ = width;
    height_ = height;
  }
  const GLuint zero = 0;
  glClearTexImage(counters_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
}

void WorkCounters::bind() const {
  glBindImageTexture(bind::kWorkCounters, counters_.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
}

std::map<std::string, double> WorkCounters::read(const std::string& prefix) const {
  std::map<std::string, double> out;
  if (!counters_ || names_.empty()) return out;
  glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
  size_t pixels = size_t(width_) * size_t(height_);
  std::vector<GLuint> values(pixels * names_.size());
  glGetTextureImage(counters_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(values.size() * sizeof(GLuint)),
                    values.data());
  double visited = 0.0;
  for (size_t p = 0; p < pixels; ++p) visited += values[p] > 0 ? 1.0 : 0.0;
  out[prefix + "_pixels"] = visited;
  for (size_t layer = 1; layer < names_.size(); ++layer) {
    double sum = 0.0, most = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
      if (values[p] == 0) continue;
      double v = values[layer * pixels + p];
      sum += v;
      most = std::max(most, v);
    }
    out[prefix + "_" + names_[layer] + "_mean"] = visited > 0.0 ? sum / visited : 0.0;
    out[prefix + "_" + names_[layer] + "_max"] = most;
  }
  return out;
}

}  // namespace vs
