// Pipeline: run. The parser: the positional arguments, then each option
// group of option_group.h, with CLI11.
#include "run/options.h"

#include "run/option_group.h"

#include <CLI/CLI.hpp>

#include <array>

namespace lray {

namespace {

const char *kDescription =
    "LRay renders a scene written as a Lua script.\n\n"
    "Every frame of <scene.lua> is rendered into <outdir> (created if missing) as\n"
    "<stem>.png for a one-frame scene, or <stem>0000.png, <stem>0001.png, ... for an\n"
    "animation. Paths inside the script are relative to the script's folder.\n\n"
    "Examples:\n"
    "  lray scenes/ring.lua out/                      render all 20 frames\n"
    "  lray scenes/ring.lua out/ --frames 5:5 -w 320  frame 5 only, 320 px wide\n"
    "  lray scene.lua out/ --backend kdtree --stats stats.json\n";

/// The groups, in the order they appear in --help and finish in.
std::array<std::unique_ptr<OptionGroup>, 5> makeGroups() {
  return {makeOutputOptions(), makeSamplingOptions(), makeLimitOptions(), makeFarmOptions(),
          makePreviewOptions()};
}

void addAll(CLI::App &app, Options &o, std::array<std::unique_ptr<OptionGroup>, 5> &groups) {
  app.set_version_flag("--version", std::string("lray ") + LRAY_VERSION);
  app.add_option("scene", o.scenePath, "Scene script (.lua)")->required();
  app.add_option("outdir", o.outDir, "Folder for the rendered images (optional with --watch)");
  for (auto &g : groups) g->add(app, o);
}

} // namespace

ParseResult parseOptions(int argc, const char *const *argv) {
  Options o;
  CLI::App app(kDescription, "lray");
  auto groups = makeGroups();
  addAll(app, o, groups);
  auto usageError = [](std::string why) {
    if (why.find("lray --help") == std::string::npos) why += " (run 'lray --help' for usage)";
    return ParseResult{std::nullopt, 2, "lray: error: " + why};
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp &) {
    return {std::nullopt, 0, app.help()};
  } catch (const CLI::CallForVersion &) {
    return {std::nullopt, 0, std::string("lray ") + LRAY_VERSION + "\n"};
  } catch (const CLI::ParseError &e) {
    return usageError(e.what());
  }
  for (auto &g : groups)
    if (std::string error = g->finish(o); !error.empty()) return usageError(error);
  if (o.outDir.empty() && !o.watch && !o.info)
    return usageError("give the folder for the images: lray <scene.lua> <outdir>");
  return {o, 0, ""};
}

std::vector<std::string> optionNames() {
  Options o;
  CLI::App app(kDescription, "lray");
  auto groups = makeGroups();
  addAll(app, o, groups);
  std::vector<std::string> names;
  auto collect = [&names](const CLI::App &a) {
    for (const CLI::Option *option : a.get_options())
      if (!option->get_lnames().empty()) names.push_back("--" + option->get_lnames().front());
  };
  collect(app);
  for (const CLI::App *group : app.get_subcommands({})) collect(*group);
  return names;
}

} // namespace lray
