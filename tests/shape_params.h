// Test helpers: the per-shape parameters the tests set on plain Entities.
#pragma once

#include "scene/scene.h"

#include <variant>

namespace lray {

/// Sets `open` on a Cylinder or Cone; other shapes have no caps to drop.
inline void setOpen(Entity &e, bool open) {
  if (auto *c = std::get_if<Cylinder>(&e.shape)) c->open = open;
  if (auto *c = std::get_if<Cone>(&e.shape)) c->open = open;
}

inline bool isOpen(const Entity &e) {
  if (auto *c = std::get_if<Cylinder>(&e.shape)) return c->open;
  if (auto *c = std::get_if<Cone>(&e.shape)) return c->open;
  return false;
}

} // namespace lray
