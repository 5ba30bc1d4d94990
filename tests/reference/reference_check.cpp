// Reference-image CI (tests/reference): renders one frame of a scene through
// the same pipeline as the CLI and compares it with its checked-in reference
// using OpenImageIO's ImageBufAlgo::compare, with idiff's thresholds:
//   --fail F         a channel differing by more than F counts as a failed pixel
//   --failpercent P  the test fails when more than P % of pixels failed
//   --hardfail H     the test fails when any channel differs by more than H
// On failure it writes the new image, the reference and an amplified
// difference into --report-dir and regenerates index.html there.
// With LRAY_UPDATE_REFERENCES=1 it (re)writes the reference instead.
#include "run/frame_pipeline.h"
#include "bindings/scene_script.h"
#include "render/image_writer.h"
#include "shading/image_cache.h"
#include "render/backends.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <vector>

namespace fs = std::filesystem;
using namespace lray;

namespace {

struct Args {
  std::string scene, reference, name, reportDir, backend = "embree";
  int frame = 0, width = 160, height = 120, samples = 2;
  double fail = 0.004, failPercent = 0, hardFail = 1;
};

OIIO::ImageBuf filmToBuf(const Film &film, bool floatImage) {
  if (floatImage) {
    OIIO::ImageSpec spec(film.width(), film.height(), 3, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf buf(spec);
    buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, film.data().data());
    return buf;
  }
  // Compare exactly what an 8-bit file would hold.
  std::vector<uint8_t> bytes = quantizeFilm(film, false);
  OIIO::ImageSpec spec(film.width(), film.height(), 3, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf buf(spec);
  buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::UINT8, bytes.data());
  return buf;
}

void writeBuf(const OIIO::ImageBuf &buf, const fs::path &path) {
  fs::path tmp =
      path.parent_path() / ("." + path.filename().string() + ".tmp" + path.extension().string());
  if (!buf.write(tmp.string()))
    throw std::runtime_error("cannot write " + path.string() + ": " + buf.geterror());
  fs::rename(tmp, path);
}

// index.html lists every failure report (*.txt) found in the folder.
void writeIndex(const fs::path &dir) {
  std::vector<fs::path> reports;
  for (const auto &e : fs::directory_iterator(dir))
    if (e.path().extension() == ".txt") reports.push_back(e.path());
  std::sort(reports.begin(), reports.end());
  std::ofstream html(dir / "index.html");
  html
      << "<!doctype html><html><head><meta charset=\"utf-8\"><title>LRay reference failures</title>"
         "<style>body{font-family:sans-serif;background:#222;color:#eee} "
         "img{image-rendering:pixelated;"
         "width:320px;border:1px solid #666} td{padding:4px;vertical-align:top} "
         "pre{color:#fc8;white-space:pre-wrap}</style>"
         "</head><body><h1>LRay reference-image failures</h1>\n";
  for (const fs::path &r : reports) {
    std::string stem = r.stem().string();
    std::ifstream in(r);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    html << "<h2>" << stem << "</h2><pre>" << text
         << "</pre><table><tr><th>new</th><th>reference</th>"
         << "<th>difference x10</th></tr><tr><td><img src=\"" << stem
         << ".new.png\"></td><td><img src=\"" << stem << ".ref.png\"></td><td><img src=\"" << stem
         << ".diff.png\"></td></tr></table>\n";
  }
  html << "</body></html>\n";
}

int check(const Args &a) {
  ScriptOptions options;
  SceneScript script(a.scene, options);
  SceneInfo info = script.info();
  info.imageWidth = a.width;
  info.imageHeight = a.height;
  info.samples = a.samples;
  ImageCache images(false);
  FrameStats stats;
  // The scene's own light transport (SceneInfo.integrator, max_depth), as lray renders it.
  FrameSettings transport;
  transport.integrator =
      info.integrator == "path" ? IntegratorKind::Path : IntegratorKind::Whitted;
  transport.maxDepth = info.maxDepth;
  Film film =
      renderScriptFrame(script, info, a.frame, a.backend, images, stats, nullptr, transport);
  if (stats.rays.nonFinite != 0) {
    std::cerr << a.name << ": " << stats.rays.nonFinite << " non-finite samples\n";
    return 1;
  }
  bool isFloat = fs::path(a.reference).extension() == ".exr";
  OIIO::ImageBuf rendered = filmToBuf(film, isFloat);

  if (const char *update = std::getenv("LRAY_UPDATE_REFERENCES");
      update && std::string(update) == "1") {
    fs::create_directories(fs::path(a.reference).parent_path());
    writeBuf(rendered, a.reference);
    std::cout << "updated " << a.reference << "\n";
    return 0;
  }

  OIIO::ImageBuf reference(a.reference);
  if (!reference.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    std::cerr << a.name << ": cannot read reference " << a.reference
              << " (run scripts/update-references): " << reference.geterror() << "\n";
    return 1;
  }
  if (reference.spec().width != a.width || reference.spec().height != a.height) {
    std::cerr << a.name << ": reference is " << reference.spec().width << "x"
              << reference.spec().height << ", render is " << a.width << "x" << a.height << "\n";
    return 1;
  }
  auto cmp = OIIO::ImageBufAlgo::compare(rendered, reference, a.fail, a.fail);
  const double pixels = static_cast<double>(a.width) * a.height;
  const double failedPercent = 100.0 * static_cast<double>(cmp.nfail) / pixels;
  std::string summary =
      fmt::format("{}: {} pixels ({:.4f} %) differ by more than {} (allowed {} %); max error "
                  "{:.5f} at ({}, {}) "
                  "(hard limit {}); mean {:.3g}, RMS {:.3g}, PSNR {:.2f} dB",
                  a.name, cmp.nfail, failedPercent, a.fail, a.failPercent, cmp.maxerror, cmp.maxx,
                  cmp.maxy, a.hardFail, cmp.meanerror, cmp.rms_error, cmp.PSNR);
  // CompareResults::error only says that some pixel exceeded --fail (sizes
  // were checked above), so the verdict is idiff's: failpercent and hardfail.
  bool failed = failedPercent > a.failPercent || cmp.maxerror > a.hardFail;
  fs::path dir = a.reportDir;
  if (!failed) {
    std::cout << "ok " << summary << "\n";
    // A report left by an earlier failing run no longer applies.
    std::error_code ec;
    if (fs::remove(dir / (a.name + ".txt"), ec) && fs::exists(dir)) writeIndex(dir);
    return 0;
  }
  fs::create_directories(dir);
  OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(rendered, reference);
  diff = OIIO::ImageBufAlgo::mul(diff, 10.0f);
  auto asBytes = [](const OIIO::ImageBuf &b) {
    OIIO::ImageBuf out(OIIO::ImageSpec(b.spec().width, b.spec().height, 3, OIIO::TypeDesc::UINT8));
    OIIO::ImageBufAlgo::copy(out, b);
    return out;
  };
  writeBuf(asBytes(rendered), dir / (a.name + ".new.png"));
  writeBuf(asBytes(reference), dir / (a.name + ".ref.png"));
  writeBuf(asBytes(diff), dir / (a.name + ".diff.png"));
  std::ofstream(dir / (a.name + ".txt")) << summary << "\n";
  writeIndex(dir);
  std::cerr << "FAILED " << summary << "\nsee " << (dir / "index.html").string() << "\n";
  return 1;
}

} // namespace

int main(int argc, char **argv) {
  Args a;
  CLI::App app("Renders a scene frame and compares it with its reference image.", "lray_refcheck");
  app.add_option("scene", a.scene)->required();
  app.add_option("reference", a.reference)->required();
  app.add_option("--name", a.name)->required();
  app.add_option("--report-dir", a.reportDir)->required();
  std::vector<std::string> names;
  for (const BackendEntry &b : backends()) names.push_back(b.name);
  app.add_option("--backend", a.backend)->check(CLI::IsMember(names));
  app.add_option("--frame", a.frame);
  app.add_option("--width", a.width);
  app.add_option("--height", a.height);
  app.add_option("--samples", a.samples);
  app.add_option("--fail", a.fail);
  app.add_option("--failpercent", a.failPercent);
  app.add_option("--hardfail", a.hardFail);
  CLI11_PARSE(app, argc, argv);
  try {
    return check(a);
  } catch (const std::exception &e) {
    std::cerr << a.name << ": error: " << e.what() << "\n";
    return 1;
  }
}
