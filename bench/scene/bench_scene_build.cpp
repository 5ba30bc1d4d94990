// Benchmark (issue 3): a procedural scene of 1,000,000 transformed spheres
// built from Lua and converted into the plain scene model. Prints the
// seconds per phase and the peak resident memory. Target: < 3 s, < 1 GiB.
//
//   bench_scene_build [sphere count]
//   bench_scene_build path/to/scene.lua   (time any scene's first frame)
#include "bindings/scene_script.h"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

double peakMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0; // Linux reports KiB
}

double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_utime.tv_usec * 1e-6 + usage.ru_stime.tv_sec +
         usage.ru_stime.tv_usec * 1e-6;
}

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

} // namespace

int main(int argc, char **argv) {
  long count = argc > 1 ? std::atol(argv[1]) : 1000000;
  // A 100 x 100 x N grid of spheres, each with its own rotation and scale,
  // all sharing one texture: the shape of a typical procedural scene.
  std::string source = "local count = " + std::to_string(count) + "\n" + R"lua(
local shared = Texture() { pigment = ColorPigment(red), finish = Finish() { specular = 0.4 } }
function scene(clock)
  local s = Scene() { camera = Perspective(60) { transform = LookAt(Vector(50, 50, -80), Vector(50, 50, 0), y) } }
  for i = 0, count - 1 do
    local p = Vector(i % 100, (i // 100) % 100, i // 10000)
    local sphere = Sphere(Translate(p) * Rotate(y, i % 360) * Scale(0.4, 0.3, 0.4))
    sphere.texture = shared
    s:add_entity(sphere)
  end
  s:add_light(Light() { transform = Translate(Vector(-50, 200, -100)) })
  return s
end
)lua";

  std::string file = argc > 1 && std::string(argv[1]).ends_with(".lua") ? argv[1] : "";
  auto start = std::chrono::steady_clock::now();
  lray::SceneScript script = file.empty()
                                 ? lray::SceneScript::fromString(source, "bench_spheres.lua")
                                 : lray::SceneScript(file);
  double loadSeconds = seconds(start);
  auto buildStart = std::chrono::steady_clock::now();
  lray::Scene scene = script.buildFrame(0);
  double buildSeconds = seconds(buildStart);
  double total = seconds(start);

  std::printf("spheres:            %zu\n", scene.entities.size());
  std::printf("textures/pigments:  %zu/%zu\n", scene.textures.size(), scene.pigments.size());
  std::printf("load script:        %.3f s\n", loadSeconds);
  std::printf("scene(0)+convert:   %.3f s\n", buildSeconds);
  std::printf("total:              %.3f s wall, %.3f s CPU (target < 3 s)\n", total, cpuSeconds());
  std::printf("peak memory:        %.0f MiB (target < 1024 MiB)\n", peakMiB());
  std::printf("plain model:        %.0f MiB (%zu bytes per Entity)\n",
              scene.entities.capacity() * sizeof(lray::Entity) / 1048576.0, sizeof(lray::Entity));
  return file.empty() && scene.entities.size() != static_cast<size_t>(count) ? 1 : 0;
}
