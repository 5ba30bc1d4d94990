#include "compare/html_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;

namespace lray::compare {

namespace {

unsigned char byte(double v) {
  if (!(v > 0)) return 0; // NaN too
  return static_cast<unsigned char>(std::lround(std::min(v, 1.0) * 255));
}

std::vector<unsigned char> bytesOf(const CompareImage &im) {
  std::vector<unsigned char> out(im.rgb.size());
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = byte(im.rgb[i]);
  return out;
}

std::vector<unsigned char> heatMap(const Outcome &o) {
  std::vector<unsigned char> out(o.heat.size() * 3);
  for (size_t i = 0; i < o.heat.size(); ++i) {
    const double h = std::isnan(o.heat[i]) ? 1 : std::clamp(o.heat[i] / o.heatScale, 0.f, 1.f);
    double r = std::min(1.0, 3 * h), g = std::clamp(3 * h - 1, 0.0, 1.0),
           b = std::clamp(3 * h - 2, 0.0, 1.0);
    if (o.flagged[i]) {
      r = 0.5 * r + 0.1;
      g = 0.5 * g + 0.45;
      b = 0.5 * b + 0.5;
    }
    out[i * 3] = byte(r);
    out[i * 3 + 1] = byte(g);
    out[i * 3 + 2] = byte(b);
  }
  return out;
}

const char *kStyle = R"(
body{font-family:system-ui,sans-serif;background:#1e1f22;color:#e8e8e8;margin:24px}
h1{font-size:22px} a{color:#9cf} .case{background:#2a2c30;border-radius:8px;padding:12px 16px;
margin:16px 0} .pass{color:#7d7} .fail{color:#f77} .error{color:#fb5} .verdict{font-family:
monospace;white-space:pre-wrap;color:#ccc} table.fig td{padding:1px 12px 1px 0;font-size:13px}
.row{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start} figure{margin:0}
figcaption{font-size:12px;color:#aaa} img{image-rendering:pixelated;display:block}
.swipe{position:relative;display:inline-block} .swipe img.top{position:absolute;left:0;top:0}
.controls{font-size:12px;color:#aaa;margin-top:4px} button{font-size:12px}
)";

const char *kScript = R"(
function swipe(r){var t=document.getElementById(r.dataset.top);t.style.clipPath=
'inset(0 '+(100-r.value)+'% 0 0)';}
function flip(id){var t=document.getElementById(id);t.style.visibility=
t.style.visibility=='hidden'?'visible':'hidden';}
)";

} // namespace

void writeCaseImages(const std::string &dir, CaseResult &r, const CompareImage &fresh,
                     const CompareImage &approved) {
  const fs::path folder = fs::path(dir) / r.name;
  fs::create_directories(folder);
  writePng((folder / "new.png").string(), fresh.width, fresh.height, bytesOf(fresh));
  writePng((folder / "approved.png").string(), approved.width, approved.height, bytesOf(approved));
  if (r.outcome)
    writePng((folder / "difference.png").string(), fresh.width, fresh.height, heatMap(*r.outcome));
  r.hasImages = true;
}

void writeHtmlReport(const std::string &dir, const std::string &title,
                     const std::vector<CaseResult> &results) {
  std::vector<const CaseResult *> order;
  for (const CaseResult &r : results)
    order.push_back(&r);
  std::stable_sort(order.begin(), order.end(), [](const CaseResult *a, const CaseResult *b) {
    return (a->status == CaseStatus::Pass) < (b->status == CaseStatus::Pass);
  });
  size_t passed = 0;
  for (const CaseResult &r : results)
    passed += r.status == CaseStatus::Pass;
  std::string html = "<!doctype html><html><head><meta charset=\"utf-8\"><title>" +
                     escapeMarkup(title) + "</title><style>" + kStyle + "</style><script>" +
                     kScript + "</script></head><body>\n";
  html += fmt::format("<h1>{}: {} of {} cases pass</h1>\n<ul>\n", escapeMarkup(title), passed,
                      results.size());
  auto statusWord = [](CaseStatus s) {
    return s == CaseStatus::Pass ? "pass" : s == CaseStatus::Fail ? "fail" : "error";
  };
  for (const CaseResult *r : order)
    html += fmt::format("<li><a href=\"#{0}\">{0}</a> <span class=\"{1}\">{1}</span></li>\n",
                        escapeMarkup(r->name), statusWord(r->status));
  html += "</ul>\n";
  int index = 0;
  for (const CaseResult *r : order) {
    const std::string name = escapeMarkup(r->name);
    html += fmt::format("<div class=\"case\" id=\"{0}\"><h2>{0} <span class=\"{1}\">{1}</span> "
                        "<small>({2:.2f} s)</small></h2>\n<div class=\"verdict\">{3}</div>\n",
                        name, statusWord(r->status), r->seconds, escapeMarkup(r->detail));
    if (r->outcome) {
      const Outcome &o = *r->outcome;
      html += "<table class=\"fig\">";
      html += fmt::format("<tr><td>metric</td><td>{}</td></tr>", metricName(r->metric));
      html += fmt::format("<tr><td>RMSE</td><td>{:.4g}</td></tr><tr><td>PSNR</td><td>{:.2f} dB"
                          "</td></tr><tr><td>SSIM</td><td>{:.5f}</td></tr>",
                          o.rmse, o.psnr, o.ssim);
      html += fmt::format("<tr><td>largest difference</td><td>{:.4g} at ({}, {})</td></tr>"
                          "<tr><td>pixels beyond 1/255</td><td>{:.3f} %</td></tr>",
                          o.maxDifference, o.maxX, o.maxY, o.failingPercent);
      if (r->metric == Metric::Noise)
        html += fmt::format("<tr><td>noise tests</td><td>{} rejected of {}, smallest p {:.3g}"
                            "</td></tr>",
                            o.noiseRejected, o.noiseTests, o.noiseMinP);
      if (o.nonFinite)
        html += fmt::format("<tr><td>non-finite pixels</td><td>{}</td></tr>", o.nonFinite);
      html += "</table>\n";
    }
    if (r->hasImages) {
      const std::string folder = escapeMarkup(r->name);
      const std::string top = fmt::format("top{}", index++);
      // Shown at twice their size (at most 640 px wide) so pixels can be seen.
      html += fmt::format(
          "<div class=\"row\">"
          "<figure><div class=\"swipe\"><img src=\"{0}/approved.png\" class=\"scaled\">"
          "<img src=\"{0}/new.png\" id=\"{1}\" class=\"top scaled\" "
          "style=\"clip-path:inset(0 50% 0 0)\"></div><div class=\"controls\">new | approved "
          "<input type=\"range\" min=\"0\" max=\"100\" value=\"50\" data-top=\"{1}\" "
          "oninput=\"swipe(this)\"> <button onclick=\"flip('{1}')\">flip</button></div>"
          "</figure>"
          "<figure><img src=\"{0}/new.png\" class=\"scaled\"><figcaption>new</figcaption>"
          "</figure><figure><img src=\"{0}/approved.png\" class=\"scaled\"><figcaption>approved"
          "</figcaption></figure>",
          folder, top);
      if (r->outcome)
        html += fmt::format("<figure><img src=\"{}/difference.png\" class=\"scaled\">"
                            "<figcaption>difference (cyan: failing)</figcaption></figure>",
                            folder);
      html += "</div>\n";
    }
    html += "</div>\n";
  }
  html += "<script>for(const i of document.querySelectorAll('img.scaled')){i.onload=function()"
          "{this.style.width=Math.min(640,2*this.naturalWidth)+'px';};if(i.complete)i.onload();}"
          "</script>\n</body></html>\n";
  writeReportFile((fs::path(dir) / "index.html").string(), html);
}

} // namespace lray::compare
