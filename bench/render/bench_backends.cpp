// bench/backends: the two acceleration backends side by side.
//  1. A scaling series of procedural scenes (spheres, and triangle meshes),
//     10^2 .. 10^6 primitives (triangles: bench/kdtree's bumpy sphere
//     mesh): build time, memory, and rays/s for primary (coherent camera
//     rays), shadow (occlusion towards a light) and secondary (incoherent:
//     random directions from the primary hits) rays; the frame time's
//     growth with N against log N's.
//  2. The same series' frames at 1280x960, where the largest scenes'
//     primitives are about pixel-sized.
//  3. The triangle series from close up (closeUpView), the control whose
//     rays keep their data in the caches at every N.
//  4. The gallery (every scenes/*.lua, frame 0): render time per backend and
//     the fraction of identical pixels.
// Writes a Markdown table and a data file for the plot (see bench/backends).
#include "render/backends.h"
#include "bench/kdtree/accelerator_bench.h"
#include "run/frame_pipeline.h"
#include "bindings/scene_script.h"
#include "math/spawn.h"
#include "math/random.h"
#include "render/camera_rays.h"
#include "render/image_writer.h"
#include "render/renderer.h"
#include "shading/image_cache.h"

#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <stdexcept>
#include <vector>

using namespace lray;
namespace fs = std::filesystem;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// N spheres at random in a unit-density box, radius chosen so the projected
// coverage stays about the same at every N.
Scene sphereScene(size_t n) {
  Scene s;
  s.textures.push_back(Texture{});
  s.pigments.push_back(Pigment{});
  Sampler rng(7, n, 0);
  double side = 10, radius = 0.6 * side / std::cbrt(static_cast<double>(n));
  for (size_t i = 0; i < n; ++i) {
    Entity e;
    e.shape = Sphere{};
    Vec3 c{(rng.next() - 0.5) * side, (rng.next() - 0.5) * side, (rng.next() - 0.5) * side};
    e.worldFromObject = Transform::translate(c) * Transform::scale(radius, radius, radius);
    s.entities.push_back(e);
  }
  s.camera.worldFromCamera = Transform::translate({0, 0, -2.2 * side});
  s.camera.fov = 40;
  return s;
}

// The triangle series seen from close up: the camera (fov 40) looks down
// +z at the mesh's surface from a distance that shrinks with the
// triangles, so the view spans about `edges` triangle edges at every N.
// The rays then touch a few leaves near one spot and the path to them:
// the structures' work per ray grows with their depth, from data that
// stays in the caches (the control for the full-view series, whose
// structures outgrow the L3).
Scene closeUpView(Scene scene, size_t triangles, double edges) {
  const Vec3 axis{0.13, 0.21, 0}; // off the poles and the grid's seams
  Ray probe;
  probe.o = axis + Vec3{0, 0, -3};
  probe.d = {0, 0, 1};
  Hit hit;
  if (!makeAccelerator(BackendKind::Embree, scene)->intersect(probe, hit))
    throw std::logic_error("closeUpView: the probe ray missed the mesh");
  const double width = edges * std::sqrt(4 * std::numbers::pi / static_cast<double>(triangles));
  const double fov = 40;
  const double distance = width / (2 * std::tan(fov / 2 * std::numbers::pi / 180));
  scene.camera.fov = fov;
  scene.camera.worldFromCamera = Transform::translate(probe.at(hit.t - distance));
  return scene;
}

struct RayFigures {
  double build = 0, memoryMB = 0, primary = 0, shadow = 0, secondary = 0; // rays/s in millions
  double primarySingle = 0; ///< the same camera rays one at a time (intersect)
  double render = 0;        ///< seconds for a whole frame through the renderer (no build)
  uint64_t renderRays = 0;  ///< rays that frame traced (camera, shadow, reflected)
  size_t hits = 0;
};

// The scaling scenes as a frame to render: one point light (the shadow rays'
// light) and a finish with some reflection, so a frame traces primary,
// shadow and reflected rays through the renderer's own tiles and shading.
Scene withLightAndFinish(Scene scene) {
  Light light;
  light.worldFromLight = Transform::translate({-30, 40, -30});
  scene.lights.push_back(light);
  for (Texture &t : scene.textures) t.finish.reflection = 0.3;
  return scene;
}

// Render time: best of three frames (the build is not part of it), and the
// rays a frame traced.
void renderFrames(const Scene &scene, const Accelerator &accel, int width, int height,
                  RayFigures &f) {
  ImageCache images(false);
  FrameSettings settings;
  settings.width = width;
  settings.height = height;
  f.render = 1e300;
  for (int i = 0; i < 3; ++i) {
    RayCounts counts;
    double t0 = now();
    Film film = renderFrame(scene, accel, images, settings, counts);
    f.render = std::min(f.render, now() - t0);
    f.renderRays = counts.camera + counts.shadow + counts.reflection + counts.refraction;
  }
}

// The scaling series' scene of kind "spheres" or "triangles" with N primitives.
Scene seriesScene(const std::string &kind, size_t n) {
  return withLightAndFinish(kind == "spheres" ? sphereScene(n) : bench::makeBumpySphereScene(n));
}

RayFigures measure(const Scene &scene, BackendKind kind, int width, int height) {
  RayFigures f;
  double t0 = now();
  auto accel = makeAccelerator(kind, scene);
  f.build = now() - t0;
  f.memoryMB = accel->stats().memoryBytes / 1048576.0;

  CameraRays camera(scene.camera, width, height);
  const size_t count = static_cast<size_t>(width) * height;
  std::vector<Ray> rays(count);
  std::vector<Hit> hits(count);
  std::vector<uint8_t> found(count);
  // Camera rays in 8x8 blocks, as the renderer's tiles issue them.
  size_t k = 0;
  for (int by = 0; by < height; by += 8)
    for (int bx = 0; bx < width; bx += 8)
      for (int y = by; y < std::min(by + 8, height); ++y)
        for (int x = bx; x < std::min(bx + 8, width); ++x)
          rays[k++] = camera.generate(x + 0.5, y + 0.5);

  t0 = now();
  for (size_t i = 0; i < count; i += 64) {
    size_t n = std::min<size_t>(64, count - i);
    accel->intersectCoherent(&rays[i], n, &hits[i], &found[i]);
  }
  f.primary = count / (now() - t0) / 1e6;
  // Issue 6 compares the kd-tree with Embree's single-ray traversal: the
  // same camera rays again, one intersect() each.
  {
    Hit h;
    size_t n = 0;
    t0 = now();
    for (const Ray &r : rays) n += accel->intersect(r, h);
    f.primarySingle = count / (now() - t0) / 1e6;
    if (n == size_t(-1)) std::cout << "";
  }

  std::vector<Ray> shadowRays, secondaryRays;
  Vec3 light{-30, 40, -30};
  Sampler rng(1, 2, 3);
  for (size_t i = 0; i < count; ++i) {
    if (!found[i]) continue;
    ++f.hits;
    shadowRays.push_back(spawnRayTo(hits[i], light));
    Vec3 d;
    do d = Vec3{rng.next() * 2 - 1, rng.next() * 2 - 1, rng.next() * 2 - 1};
    while (dot(d, d) > 1 || dot(d, d) < 1e-6);
    if (dot(d, hits[i].ng) < 0) d = -d;
    secondaryRays.push_back(spawnRay(hits[i], d));
  }
  if (!shadowRays.empty()) {
    size_t blocked = 0;
    t0 = now();
    for (const Ray &r : shadowRays) blocked += accel->occluded(r);
    f.shadow = shadowRays.size() / (now() - t0) / 1e6;
    Hit h;
    t0 = now();
    for (const Ray &r : secondaryRays) blocked += accel->intersect(r, h);
    f.secondary = secondaryRays.size() / (now() - t0) / 1e6;
    if (blocked == size_t(-1)) std::cout << ""; // keep the loops from being optimised away
  }
  renderFrames(scene, *accel, width, height, f);
  return f;
}

/// Growth of a per-frame time from the smallest to the largest N of a
/// series, next to the growth of log N over the same range.
std::string logGrowthLine(const char *what, double tSmall, double tLarge, size_t nSmall,
                          size_t nLarge) {
  double growth = tLarge / tSmall;
  double logGrowth = std::log(double(nLarge)) / std::log(double(nSmall));
  return fmt::format("| {} | {:.2f}x | {:.2f}x | {} |\n", what, growth, logGrowth,
                     growth <= logGrowth ? "yes" : "no");
}

// One backend's figures at every N of a series.
struct Point {
  size_t n = 0;
  double render = 0, perRay = 0;         ///< frame seconds, and per traced ray
  double camera = 0, shadow = 0, secondary = 0; ///< seconds per ray of each set, backend only
};
struct Series {
  BackendKind backend;
  std::string kind; ///< "spheres" or "triangles"
  std::string view; ///< how the series is rendered, for its label ("" for the first)
  std::vector<Point> points;

  std::string label() const {
    return fmt::format("{} {}{}{}", backendName(backend), kind, view.empty() ? "" : ", ", view);
  }
};

void addPoint(std::vector<Series> &all, BackendKind backend, const std::string &kind,
              const std::string &view, size_t n, const RayFigures &f) {
  auto it = std::find_if(all.begin(), all.end(), [&](const Series &s) {
    return s.backend == backend && s.kind == kind;
  });
  if (it == all.end()) it = all.insert(all.end(), Series{backend, kind, view, {}});
  it->points.push_back({n, f.render, f.render / static_cast<double>(f.renderRays),
                        f.primarySingle > 0 ? 1e-6 / f.primarySingle : 0,
                        f.shadow > 0 ? 1e-6 / f.shadow : 0,
                        f.secondary > 0 ? 1e-6 / f.secondary : 0});
}

// Largest against smallest N: the frame, and (raySets) each ray set alone.
void writeGrowth(std::ostream &md, const std::vector<Series> &all, bool raySets) {
  md << "| backend, series | growth | log N growth | within log N |\n|---|---|---|---|\n";
  for (const Series &s : all) {
    const Point &a = s.points.front(), &z = s.points.back();
    auto line = [&](const char *what, double small, double large) {
      md << logGrowthLine(fmt::format("{}: {}", s.label(), what).c_str(), small, large, a.n,
                          z.n);
    };
    line("frame time", a.render, z.render);
    line("frame time per traced ray", a.perRay, z.perRay);
    if (!raySets) continue;
    line("one camera ray, backend only", a.camera, z.camera);
    line("one shadow ray, backend only", a.shadow, z.shadow);
    line("one secondary ray, backend only", a.secondary, z.secondary);
  }
}

// Decade by decade, frame time per traced ray, beside log N's growth.
void writeDecades(std::ostream &md, const std::vector<Series> &all) {
  if (all.empty() || all.front().points.size() < 2) return;
  const std::vector<Point> &ns = all.front().points;
  md << "| backend, series |";
  for (size_t i = 1; i < ns.size(); ++i) md << fmt::format(" {} -> {} |", ns[i - 1].n, ns[i].n);
  md << "\n|---|";
  for (size_t i = 1; i < ns.size(); ++i) md << "---|";
  md << "\n| log N |";
  for (size_t i = 1; i < ns.size(); ++i)
    md << fmt::format(" {:.2f}x |", std::log(double(ns[i].n)) / std::log(double(ns[i - 1].n)));
  md << "\n";
  for (const Series &s : all) {
    md << "| " << s.label() << " |";
    for (size_t i = 1; i < s.points.size(); ++i)
      md << fmt::format(" {:.2f}x |", s.points[i].perRay / s.points[i - 1].perRay);
    md << "\n";
  }
}

// Width of the close-up view in triangle edges.
constexpr double kCloseUpEdges = 2;
// The frame size of the series' first run and of the close-up series.
constexpr int kWidth = 320, kHeight = 240;
// The frame size of the series' second run.
constexpr int kSampledWidth = 1280, kSampledHeight = 960;

} // namespace

int main(int argc, char **argv) {
  fs::path outDir = argc > 1 ? argv[1] : "bench-backends";
  fs::path sceneDir = argc > 2 ? argv[2] : fs::path(LRAY_SOURCE_DIR) / "scenes";
  size_t maxN = argc > 3 ? std::stoul(argv[3]) : 1000000;
  fs::create_directories(outDir);
  // One thread: the figures are per-core throughput, comparable across machines.
  tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);

  std::ofstream md(outDir / "backends.md");
  std::ofstream dat(outDir / "backends.dat");
  md << fmt::format("## Scaling series (one thread, {}x{} rays)\n\n", kWidth, kHeight)
     << "| scene | N | backend | build s | memory MB | primary Mrays/s | primary single Mrays/s | "
        "shadow Mrays/s | secondary Mrays/s | render s | render rays |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
  dat << "# kind N embree_build kd_build embree_mem kd_mem embree_primary kd_primary embree_shadow "
         "kd_shadow embree_secondary kd_secondary embree_primary_single kd_primary_single "
         "embree_render kd_render\n";
  // Per backend and kind, at every N of the series, for the growth tables
  // below (largest against smallest N, and decade by decade).
  std::vector<Series> series;
  for (const char *kind : {"spheres", "triangles"}) {
    for (size_t n = 100; n <= maxN; n *= 10) {
      Scene scene = seriesScene(kind, n);
      RayFigures fig[2];
      for (int b = 0; b < 2; ++b) {
        BackendKind backend = b == 0 ? BackendKind::Embree : BackendKind::KdTree;
        fig[b] = measure(scene, backend, kWidth, kHeight);
        md << fmt::format(
            "| {} | {} | {} | {:.3f} | {:.1f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.3f} | {} "
            "|\n",
            kind, n, backendName(backend), fig[b].build, fig[b].memoryMB, fig[b].primary,
            fig[b].primarySingle, fig[b].shadow, fig[b].secondary, fig[b].render,
            fig[b].renderRays);
        addPoint(series, backend, kind, "", n, fig[b]);
        std::cout << kind << " " << n << " " << backendName(backend) << " build " << fig[b].build
                  << " s, primary " << fig[b].primary << " Mrays/s" << std::endl;
      }
      md << fmt::format("| {} | {} | kd/embree | {:.2f}x | {:.2f}x | {:.2f}x | {:.2f}x | {:.2f}x | "
                        "{:.2f}x | {:.2f}x | |\n",
                        kind, n, fig[1].build / fig[0].build, fig[1].memoryMB / fig[0].memoryMB,
                        fig[1].primary / fig[0].primary,
                        fig[1].primarySingle / fig[0].primarySingle,
                        fig[1].shadow / fig[0].shadow, fig[1].secondary / fig[0].secondary,
                        fig[1].render / fig[0].render);
      dat << fmt::format("{} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {}\n", kind, n,
                         fig[0].build, fig[1].build, fig[0].memoryMB, fig[1].memoryMB,
                         fig[0].primary, fig[1].primary, fig[0].shadow, fig[1].shadow,
                         fig[0].secondary, fig[1].secondary, fig[0].primarySingle,
                         fig[1].primarySingle, fig[0].render, fig[1].render);
    }
  }

  // Render time against log N: a frame of the largest scene may take at most
  // log(N_max) / log(N_min) times the smallest one's. The frame time is what
  // a user waits for (camera rays, shading, shadow and reflected rays); as
  // the series' scenes do not trace the same number of rays (more pixels hit
  // the many small spheres than the few big ones), the frame time per traced
  // ray follows it, then each ray set alone, through the backend only (no
  // shading): the Embree rows there are Embree's own traversal.
  md << "\n## Growth with N (largest / smallest scene of the series)\n\n";
  writeGrowth(md, series, true);
  // Decade by decade: where the time per traced ray outgrows log N. Once a
  // structure leaves a cache level, every backend's rays pay its misses.
  md << "\n## Growth decade by decade (frame time per traced ray)\n\n";
  writeDecades(md, series);

  // The same series at 1280x960: a frame of the 10^6-triangle mesh then
  // has about one visible triangle per pixel (at 320x240, 16), so
  // neighbouring rays share leaves, as in a render at a usable resolution.
  md << fmt::format("\n## Series at {}x{} (frames only; about one triangle per pixel at "
                    "10^6)\n\n",
                    kSampledWidth, kSampledHeight)
     << "| scene | N | backend | render s | render rays | ns per traced ray |\n"
        "|---|---|---|---|---|---|\n";
  std::vector<Series> sampled;
  for (const char *kind : {"spheres", "triangles"}) {
    for (size_t n = 100; n <= maxN; n *= 10) {
      Scene scene = seriesScene(kind, n);
      for (BackendKind backend : {BackendKind::Embree, BackendKind::KdTree}) {
        RayFigures fig;
        renderFrames(scene, *makeAccelerator(backend, scene), kSampledWidth, kSampledHeight, fig);
        md << fmt::format("| {} | {} | {} | {:.3f} | {} | {:.1f} |\n", kind, n,
                          backendName(backend), fig.render, fig.renderRays,
                          1e9 * fig.render / double(fig.renderRays));
        addPoint(sampled, backend, kind, fmt::format("{}x{}", kSampledWidth, kSampledHeight), n,
                 fig);
      }
    }
  }
  md << "\n### Growth with N at the larger size (largest / smallest)\n\n";
  writeGrowth(md, sampled, false);
  md << "\n### Growth decade by decade at the larger size (frame time per traced ray)\n\n";
  writeDecades(md, sampled);

  // The control: the triangle series seen from close up (closeUpView), so
  // that the rays' data stays in the caches at every N.
  md << "\n## Close-up series (triangles; the view spans about " << kCloseUpEdges
     << " triangle edges at every N)\n\n"
        "| N | backend | render s | render rays | camera hits | ns per traced ray |\n"
        "|---|---|---|---|---|---|\n";
  std::vector<Series> closeUp;
  for (size_t n = 100; n <= maxN; n *= 10) {
    Scene scene = withLightAndFinish(closeUpView(bench::makeBumpySphereScene(n), n, kCloseUpEdges));
    for (BackendKind backend : {BackendKind::Embree, BackendKind::KdTree}) {
      RayFigures fig = measure(scene, backend, kWidth, kHeight);
      md << fmt::format("| {} | {} | {:.4f} | {} | {:.1f} % | {:.1f} |\n", n, backendName(backend),
                        fig.render, fig.renderRays, 100.0 * fig.hits / (kWidth * kHeight),
                        1e9 * fig.render / double(fig.renderRays));
      addPoint(closeUp, backend, "triangles", "close up", n, fig);
    }
  }
  md << "\n### Growth with N, close up (largest / smallest)\n\n";
  writeGrowth(md, closeUp, false);
  md << "\n### Growth decade by decade, close up (frame time per traced ray)\n\n";
  writeDecades(md, closeUp);

  // The plot's growth panels: frame time per traced ray over the smallest
  // N's, both backends side by side, per view and kind.
  std::ofstream growthDat(outDir / "growth.dat");
  growthDat << "# view kind N embree kd (frame time per traced ray / the smallest N's)\n";
  auto writeGrowthDat = [&](const char *view, const std::vector<Series> &all) {
    for (const Series &e : all) {
      if (e.backend != BackendKind::Embree) continue;
      auto k = std::find_if(all.begin(), all.end(), [&](const Series &s) {
        return s.backend == BackendKind::KdTree && s.kind == e.kind;
      });
      if (k == all.end()) continue;
      for (size_t j = 0; j < e.points.size() && j < k->points.size(); ++j)
        growthDat << fmt::format("{} {} {} {} {}\n", view, e.kind, e.points[j].n,
                                 e.points[j].perRay / e.points[0].perRay,
                                 k->points[j].perRay / k->points[0].perRay);
    }
  };
  writeGrowthDat("full", series);
  writeGrowthDat("sampled", sampled);
  writeGrowthDat("closeup", closeUp);

  md << "\n## Gallery (frame 0, scene_info size, one thread)\n\n"
        "| scene | embree s | kd-tree s | kd/embree | identical pixels |\n|---|---|---|---|---|\n";
  std::vector<fs::path> scenes;
  for (const auto &e : fs::directory_iterator(sceneDir))
    if (e.path().extension() == ".lua") scenes.push_back(e.path());
  std::sort(scenes.begin(), scenes.end());
  for (const fs::path &p : scenes) {
    try {
      SceneScript script(p.string());
      SceneInfo info = script.info();
      ImageCache images(false);
      FrameStats st[2];
      Film e = renderScriptFrame(script, info, 0, backendName(BackendKind::Embree), images, st[0]);
      Film k = renderScriptFrame(script, info, 0, backendName(BackendKind::KdTree), images, st[1]);
      std::vector<uint8_t> a = quantizeFilm(e, false), b = quantizeFilm(k, false);
      size_t same = 0, pixels = a.size() / 3;
      for (size_t i = 0; i < pixels; ++i)
        same += std::equal(&a[3 * i], &a[3 * i + 3], &b[3 * i]);
      double te = st[0].renderSeconds + st[0].accel.buildSeconds;
      double tk = st[1].renderSeconds + st[1].accel.buildSeconds;
      md << fmt::format("| {} | {:.3f} | {:.3f} | {:.2f}x | {:.4f} % |\n", p.stem().string(), te,
                        tk, tk / te, 100.0 * same / pixels);
      std::cout << p.stem().string() << " embree " << te << " s, kdtree " << tk << " s"
                << std::endl;
    } catch (const std::exception &ex) {
      md << "| " << p.stem().string() << " | error: " << ex.what() << " | | | |\n";
    }
  }
  std::cout << "wrote " << (outDir / "backends.md").string() << std::endl;
  return 0;
}
