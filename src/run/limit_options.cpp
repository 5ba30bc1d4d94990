// Pipeline: run. The limits a stranger's scene runs under (README.md,
// "Security"): the script's sandbox, time and memory, and the sizes LRay
// refuses; they fill the script's ScriptOptions.
#include "run/limit_options.h"

#include "run/option_group.h"
#include "run/option_text.h"

#include <algorithm>

namespace lray {

namespace {

class LimitOptions final : public OptionGroup {
public:
  void add(CLI::App &app, Options &o) override {
    const CLI::Validator positive = option_text::finiteNumber(false);
    CLI::App &g = *app.add_option_group("Limits");
    g.add_flag("--unsafe", o.unsafe,
               "Give the script the full Lua standard library (os, io write access)");
    g.add_option("--script-timeout", o.scriptTimeout,
                 "Abort a script that runs longer than SECONDS (default 60)")
        ->check(positive);
    g.add_option("--allow-read", o.allowRead,
                 "Let the script read files below DIR too (repeatable; by default only below "
                 "the scene's folder)")
        ->type_name("DIR");
    g.add_option("--max-file-size", maxFileSize_,
                 "Refuse a scene or OBJ file larger than SIZE (bytes, or with K, M or G; "
                 "default 1G)")
        ->type_name("SIZE");
    g.add_option("--script-memory", scriptMemory_,
                 "Stop a script whose Lua memory grows past SIZE (bytes, or with K, M or G; "
                 "default 2G)")
        ->type_name("SIZE");
    g.add_option("--render-memory", renderMemory_,
                 "Refuse a frame whose scene model, textures and acceleration structure "
                 "would take more than SIZE (bytes, or with K, M or G; default half the "
                 "memory the process may have, at least 256M)")
        ->type_name("SIZE");
    g.add_option("--max-light-samples", o.maxLightSamples,
                 "Refuse a light with more shadow rays per shading point (rows*cols) than "
                 "this (default 65536)")
        ->check(positive);
    g.add_option("--max-pixels", o.maxPixels,
                 "Refuse renders with width*height*samples^2 above this (default 1e9)")
        ->check(positive);
  }

  std::string finish(Options &o) override {
    std::string error;
    if (!scriptMemory_.empty())
      error = option_text::parseSize(scriptMemory_, "--script-memory", o.scriptMemory);
    if (error.empty() && !renderMemory_.empty())
      error = option_text::parseSize(renderMemory_, "--render-memory", o.renderMemory);
    if (error.empty() && !maxFileSize_.empty())
      error = option_text::parseSize(maxFileSize_, "--max-file-size", o.maxFileBytes);
    return error;
  }

private:
  std::string maxFileSize_, scriptMemory_, renderMemory_;
};

} // namespace

std::unique_ptr<OptionGroup> makeLimitOptions() { return std::make_unique<LimitOptions>(); }

ScriptOptions scriptOptionsOf(const Options &opt) {
  ScriptOptions s;
  s.unsafe = opt.unsafe;
  s.timeoutSeconds = opt.scriptTimeout;
  s.memoryLimitBytes = opt.scriptMemory;
  s.renderMemoryBytes = opt.renderMemory;
  s.allowRead = opt.allowRead;
  s.maxFileBytes = opt.maxFileBytes;
  s.maxPixels = opt.maxPixelCount();
  s.maxLightSamples = static_cast<uint64_t>(std::min(opt.maxLightSamples, 4e18));
  return s;
}

} // namespace lray
