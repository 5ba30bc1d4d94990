// Pipeline: run. The live preview's options (--watch, --serve; app/watch/).
#include "run/option_group.h"
#include "run/option_text.h"

namespace lray {

namespace {

class PreviewOptions final : public OptionGroup {
public:
  void add(CLI::App &app, Options &o) override {
    CLI::App &g = *app.add_option_group("Live preview");
    g.add_flag("--watch", o.watch,
               "Live preview: render progressively, and again whenever the scene or a file it "
               "read changes; the image goes to <outdir> (if given) and to the page of --serve");
    serve_ = g.add_option("--serve", o.serve,
                          "With --watch: serve the preview page at HOST:PORT (default "
                          "127.0.0.1:8765, loopback only)")
                 ->type_name("HOST:PORT")
                 ->expected(0, 1);
  }

  std::string finish(Options &o) override {
    if (serve_->count() > 0 && o.serve.empty()) o.serve = "127.0.0.1:8765";
    if (!o.serve.empty()) {
      if (!o.watch) return "--serve shows the live preview of --watch: give --watch too";
      const size_t colon = o.serve.rfind(':');
      const std::string port = colon == std::string::npos ? "" : o.serve.substr(colon + 1);
      if (colon == std::string::npos || colon == 0 || port.empty() || port.size() > 5 ||
          port.find_first_not_of("0123456789") != std::string::npos || std::stoi(port) > 65535)
        return "--serve '" + o.serve + "': expected HOST:PORT, e.g. 127.0.0.1:8765";
      o.serveHost = o.serve.substr(0, colon);
      if (o.serveHost.size() > 2 && o.serveHost.front() == '[' && o.serveHost.back() == ']')
        o.serveHost = o.serveHost.substr(1, o.serveHost.size() - 2);
      o.servePort = std::stoi(port);
    }
    if (o.watch && (o.tile || o.crop || o.info || o.skipExisting || o.timeLimit > 0))
      return "--watch renders whole frames until the scene changes: --tile, --crop, "
             "--info, --skip-existing and --time-limit do not apply to it";
    return {};
  }

private:
  CLI::Option *serve_ = nullptr;
};

} // namespace

std::unique_ptr<OptionGroup> makePreviewOptions() { return std::make_unique<PreviewOptions>(); }

} // namespace lray
