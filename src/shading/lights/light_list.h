// Pipeline: shading. The one list of light kinds: a scene light is one of
// these, and the integrator's one light loop reaches each kind's sampler
// through std::visit. Adding a light: its file in this folder, one entry
// in each variant here, one registration in bindings/register_scene.cpp
// (README.md, "Adding a light").
#pragma once

#include "shading/lights/light.h"
#include "shading/lights/spot_light.h"

#include <variant>

namespace lray {

/// A light of the scene with its parameters.
using SceneLight = std::variant<Light, SpotLight>;

/// A light prepared for sampling (one per emitting light, per frame).
using LightSampler = std::variant<Light::Sampler, SpotLight::Sampler>;

/// `motion`: where the light moves while the shutter is open, or null.
inline LightSampler prepareLight(const SceneLight &light, const LightMotion *motion = nullptr) {
  return std::visit(
      [motion](const auto &l) -> LightSampler {
        typename std::decay_t<decltype(l)>::Sampler s(l);
        s.setMotion(motion);
        return s;
      },
      light);
}

inline bool lightEmits(const LightSampler &light) {
  return std::visit([](const auto &l) { return l.emits(); }, light);
}

} // namespace lray
