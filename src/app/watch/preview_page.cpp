// Pipeline: application (live preview). The page the preview server
// serves: the image as it refines, its status, the script's error, and the
// controls. Self-contained (no external script, style or font), updated by
// server-sent events; works on a phone-sized screen.
#include "app/watch/preview_server.h"

namespace lray {

const std::string &previewPage() {
  static const std::string page = R"html(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>LRay preview</title>
<style>
  :root { color-scheme: dark; font: 15px/1.4 system-ui, sans-serif; }
  body { margin: 0; background: #16181d; color: #e6e6e6; }
  [hidden] { display: none !important; }
  header { display: flex; flex-wrap: wrap; gap: .5rem 1rem; align-items: center;
           padding: .6rem 1rem; background: #22252c; }
  header h1 { font-size: 1rem; margin: 0; font-weight: 600; }
  #scene { color: #9aa3b2; overflow-wrap: anywhere; }
  main { padding: 1rem; display: grid; gap: 1rem; }
  #view { text-align: center; }
  #image { min-width: min(100%, 480px); max-width: 100%; height: auto;
           image-rendering: pixelated; background: #000; border-radius: 4px; }
  #status { font-variant-numeric: tabular-nums; color: #c8cdd6; }
  #error { display: none; white-space: pre-wrap; background: #4a1d1d; color: #ffd7d7;
           border: 1px solid #a33; padding: .6rem .8rem; border-radius: 4px;
           font-family: ui-monospace, monospace; }
  .controls { display: flex; flex-wrap: wrap; gap: .6rem 1.2rem; align-items: center; }
  .controls label { display: flex; gap: .4rem; align-items: center; }
  #frame { width: min(22rem, 60vw); }
  button, select { font: inherit; background: #2f3440; color: inherit;
                   border: 1px solid #4a5060; border-radius: 4px; padding: .3rem .7rem; }
  button:hover { background: #3a4050; }
  details pre { overflow-x: auto; font-size: .8rem; background: #1e2127; padding: .6rem;
                border-radius: 4px; }
  .state-rendering { color: #ffd479; }
  .state-done { color: #8fe08f; }
  .state-error { color: #ff8a8a; }
</style>
</head>
<body>
<header>
  <h1>LRay preview</h1>
  <span id="scene"></span>
  <span id="state" class="state-starting">starting</span>
</header>
<main>
  <div id="error" role="alert"></div>
  <div id="view"><img id="image" alt="" data-version="0" hidden></div>
  <div id="status">waiting for the first image</div>
  <div class="controls">
    <label id="frameBox" hidden>frame
      <input id="frame" type="range" min="0" max="0" value="0"><span id="frameNo">0</span>
    </label>
    <label>backend <select id="backend"></select></label>
    <button id="save" type="button">Save image</button>
    <span id="saved"></span>
  </div>
  <details><summary>Statistics of the last pass</summary><pre id="stats">{}</pre></details>
</main>
<script>
"use strict";
const $ = id => document.getElementById(id);
let shown = 0, dragging = false;
function post(path, body) {
  return fetch(path, { method: "POST", headers: { "Content-Type": "application/json" },
                       body: JSON.stringify(body || {}) });
}
function update(s) {
  $("scene").textContent = s.scene;
  $("state").textContent = s.state;
  $("state").className = "state-" + s.state;
  const err = $("error");
  err.style.display = s.message ? "block" : "none";
  err.textContent = s.message;
  if (s.has_image && s.image_version !== shown) {
    shown = s.image_version;
    // Loaded off screen, then put in place of the shown one: the page never
    // shows (or reads back) a half-loaded image.
    const img = new Image(), version = shown;
    img.alt = "the render";
    img.onload = () => {
      if (version !== shown) return; // a newer one is on its way
      img.id = "image";
      img.dataset.version = String(version);
      $("image").replaceWith(img);
    };
    img.src = "/image.png?v=" + version;
  }
  if (s.width) {
    const passName = s.pass === 0 ? "first look" : "pass " + s.pass;
    $("status").textContent = s.width + " x " + s.height + " · " + passName + " · " +
      s.samples_per_pixel.toFixed(1) + " samples/pixel · " + s.seconds.toFixed(2) +
      " s · error mean " + s.error_mean.toFixed(4) + ", max " + s.error_max.toFixed(4);
  }
  $("frameBox").hidden = s.frames <= 1;
  $("frame").max = String(Math.max(0, s.frames - 1));
  if (!dragging) {
    $("frame").value = String(s.frame);
    $("frameNo").textContent = s.frame + " (clock " + s.clock.toFixed(3) + ")";
  }
  const sel = $("backend");
  if (sel.options.length !== s.backends.length)
    sel.replaceChildren(...s.backends.map(b => new Option(b, b)));
  sel.value = s.backend;
  $("stats").textContent = JSON.stringify(s.stats, null, 1);
  document.body.dataset.state = s.state;
  document.body.dataset.version = String(s.version);
}
const events = new EventSource("/events");
events.onmessage = e => update(JSON.parse(e.data));
events.onerror = () => {
  $("state").textContent = "disconnected (is lray --watch still running?)";
  $("state").className = "state-error";
};
$("frame").addEventListener("input", () => {
  dragging = true;
  $("frameNo").textContent = $("frame").value;
});
$("frame").addEventListener("change", () => {
  dragging = false;
  post("/control", { frame: Number($("frame").value) });
});
$("backend").addEventListener("change", () => post("/control", { backend: $("backend").value }));
$("save").addEventListener("click", async () => {
  const r = await post("/save");
  $("saved").textContent =
    r.ok ? "saved " + (await r.json()).path : "not saved: " + (await r.text());
});
</script>
</body>
</html>
)html";
  return page;
}

} // namespace lray
