// Pipeline: render. Renders one frame of a converted scene with a built
// backend, whichever it is, through the table of render/backends.h.
#pragma once

#include "accel/accelerator.h"
#include "render/film.h"
#include "render/frame_settings.h"
#include "scene/scene.h"
#include "shading/ray_counts.h"

namespace lray {

class ImageCache;

/// Renders `scene` into a new film with `accel` (built over it by a
/// backend of render/backends.h) and the integrator `settings` names.
/// Adds the rays traced, by kind, to `counts`. Non-finite sample values are
/// replaced by black and counted.
Film renderFrame(const Scene &scene, const Accelerator &accel, const ImageCache &images,
                 const FrameSettings &settings, RayCounts &counts,
                 const ProgressFn &progress = nullptr);

} // namespace lray
