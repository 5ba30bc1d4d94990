// Pipeline: run. The output options: image format and encoding, extra
// layers, statistics and progress output (Options' output fields).
#include "run/option_group.h"
#include "run/option_text.h"

namespace lray {

namespace {

class OutputOptions final : public OptionGroup {
public:
  void add(CLI::App &app, Options &o) override {
    CLI::App &g = *app.add_option_group("Output");
    g.add_option("-f,--format", format_, "Output format: png (default), tga or exr")
        ->type_name("FORMAT");
    g.add_flag("--linear", o.linear,
               "Linear workflow: decode 8-bit textures from sRGB, encode 8-bit outputs to sRGB");
    g.add_flag("--aovs", o.aovs,
               "EXR output: add depth (Z), normal (N.X/N.Y/N.Z) and albedo "
               "(Albedo.R/G/B) layers for denoisers and compositors");
    g.add_flag("-q,--quiet", o.quiet, "No progress bar or informational output");
    g.add_option("--stats", o.statsPath,
                 "Write render statistics as JSON to FILE (times, rays by kind, memory, the "
                 "settings rendered with)");
  }

  std::string finish(Options &o) override {
    const std::map<std::string, ImageFormat> formats{
        {"png", ImageFormat::Png}, {"tga", ImageFormat::Tga}, {"exr", ImageFormat::Exr}};
    if (!format_.empty()) {
      std::string error = option_text::lookUp(format_, formats, "--format", "png, tga or exr",
                                              o.format);
      if (!error.empty()) return error;
    }
    if (o.aovs && o.format != ImageFormat::Exr)
      return "--aovs needs EXR output (--format exr): PNG and TGA hold only RGB";
    return {};
  }

private:
  std::string format_;
};

} // namespace

std::unique_ptr<OptionGroup> makeOutputOptions() { return std::make_unique<OutputOptions>(); }

} // namespace lray
