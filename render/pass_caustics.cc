#include "render/pass_caustics.h"

#include <chrono>

#include "render/meshes.h"

namespace ripple::render::internal {

CausticsKey CausticsKey::Of(const SceneInputs& scene) {
  CausticsKey k;
  if (scene.water.heights != nullptr) k.counter = scene.water.change_counter;
  k.light = glm::normalize(scene.light_in_tank);
  k.tank = scene.tank;
  return k;
}

bool CausticsKey::Same(const CausticsKey& o) const {
  return SameTank(tank, o.tank) && counter == o.counter &&
         glm::length(light - o.light) < 1e-9;
}

void CausticsPass::Create(const CausticsOptions& options) {
  options_ = options;
  const int c = options.map_nx;
  map_.assign(static_cast<size_t>(c) * c, 1.0f);
  AllocTexture(&texture_, GL_R32F, c, c, GL_RED, GL_FLOAT, GL_LINEAR,
               GL_CLAMP_TO_EDGE, map_.data());
  key_.reset();
  uploaded_ = true;
}

bool CausticsPass::Trace(const SceneInputs& scene, double* ms) {
  *ms = 0;
  const CausticsKey key = CausticsKey::Of(scene);
  if (key_ && key_->Same(key)) return false;
  const auto t0 = std::chrono::steady_clock::now();
  const HeightFieldView& surface = scene.caustics_water.heights != nullptr
                                       ? scene.caustics_water
                                       : scene.water;
  ComputeCaustics(options_, surface, scene.tank, key.light, &map_, nullptr,
                  &workspace_);
  double sum = 0;
  for (const float v : map_) sum += v;
  mean_ = map_.empty() ? 1.0f : static_cast<float>(sum / map_.size());
  key_ = key;
  uploaded_ = false;
  *ms = std::chrono::duration<double, std::milli>(
            std::chrono::steady_clock::now() - t0)
            .count();
  return true;
}

bool CausticsPass::Update(const SceneInputs& scene, double* ms) {
  const bool traced = Trace(scene, ms);
  if (!uploaded_) {
    glBindTexture(GL_TEXTURE_2D, texture_.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, options_.map_nx, options_.map_ny,
                    GL_RED, GL_FLOAT, map_.data());
    uploaded_ = true;
  }
  return traced;
}

}  // namespace ripple::render::internal
