// Pipeline: run. The options that split a render into parts (render farms,
// scripts/farm): which frames, which pixels, skipping finished outputs, and
// --info, which describes the parts without rendering (run_plan.h).
#include "run/option_group.h"
#include "run/option_text.h"

namespace lray {

namespace {

using option_text::valueError;

class FarmOptions final : public OptionGroup {
public:
  void add(CLI::App &app, Options &o) override {
    CLI::App &g = *app.add_option_group("Frames, tiles and farms");
    g.add_flag("--info", o.info,
               "Load the scene and print its frames, size, sampling, settings and output file "
               "names as one line of JSON (with the overrides given), render nothing; no "
               "outdir needed");
    g.add_option("--tiles", o.infoTiles,
                 "With --info: also list the N tile file names of each frame (lray --tile I/N)")
        ->type_name("N")
        ->check(CLI::Range(1, 1 << 20));
    g.add_option("--frames", frames_,
                 "Render frames A to B inclusive, numbered from 0 as in the file names "
                 "(A:B, A:B:STEP for every STEP-th, or A for one frame)");
    g.add_flag("--skip-existing", o.skipExisting,
               "Do not render a frame (or tile) whose output file already exists as a "
               "complete image of the right size: resume an interrupted animation");
    g.add_option("--tile", tile_,
                 "Render only band I (0-based) of N bands of rows of each frame, written as "
                 "<frame>.tile-I-of-N.exr; lray-merge stitches the bands into the frame")
        ->type_name("I/N");
    g.add_option("--crop", crop_,
                 "Render only the pixels x0 <= x < x1, y0 <= y < y1 of each frame, written as "
                 "<frame>.crop-x0-y0-x1-y1.exr (the general form of --tile)")
        ->type_name("x0:y0:x1:y1");
  }

  std::string finish(Options &o) override {
    std::vector<int> n;
    if (!frames_.empty()) {
      // "A", "A:B" or "A:B:STEP": non-negative integers, 0-based.
      if (!option_text::numbers(frames_, ':', n) || n.size() > 3)
        return valueError("--frames", frames_,
                          "expected A:B, A:B:STEP or A (0-based frame numbers)");
      const int a = n[0], b = n.size() > 1 ? n[1] : n[0];
      if (b < a)
        return valueError("--frames", frames_,
                          "the last frame (" + std::to_string(b) + ") comes before the first (" +
                              std::to_string(a) + ")");
      if (n.size() == 3 && n[2] == 0)
        return valueError("--frames", frames_, "the step must be 1 or more");
      o.firstFrame = a;
      o.lastFrame = b;
      o.frameStep = n.size() == 3 ? n[2] : 1;
    }
    if (!tile_.empty()) {
      if (!option_text::numbers(tile_, '/', n) || n.size() != 2)
        return valueError("--tile", tile_, "expected I/N, tile I (0-based) of N");
      if (n[1] == 0 || n[0] >= n[1])
        return valueError("--tile", tile_, "I must be below N (tiles are numbered from 0)");
      o.tile = std::pair<int, int>(n[0], n[1]);
    }
    if (!crop_.empty()) {
      if (!option_text::numbers(crop_, ':', n) || n.size() != 4)
        return valueError("--crop", crop_, "expected x0:y0:x1:y1, pixel coordinates");
      if (n[2] <= n[0] || n[3] <= n[1])
        return valueError("--crop", crop_,
                          "the window is empty (x1 must be above x0, y1 above y0)");
      o.crop = PixelWindow{n[0], n[1], n[2], n[3]};
    }
    if (o.tile && o.crop) return "--tile and --crop both choose the pixels: give one";
    if (o.infoTiles && !o.info) return "--tiles lists tile names for --info: give --info too";
    return {};
  }

private:
  std::string frames_, tile_, crop_;
};

} // namespace

std::unique_ptr<OptionGroup> makeFarmOptions() { return std::make_unique<FarmOptions>(); }

} // namespace lray
