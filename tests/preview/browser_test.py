#!/usr/bin/python3
"""The live preview in a real browser (issue 22): headless Chromium opens the
page of `lray --watch --serve`, waits for the finished image and checks its
pixels against a direct render of the same scene at the same sampling; then
edits the scene (a colour) and waits for the new picture; writes a syntax
error and checks the page shows file:line with the previous image kept; fixes
it; switches backend from the page. Every wait is bounded and waits for an
event the page shows (its data attributes), never a fixed sleep. Leaves a
screenshot of the page (--screenshot PATH).

  browser_test.py --lray build/lray [--screenshot out.png]
"""
import argparse
import base64
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

from selenium import webdriver
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.support.ui import WebDriverWait

SCENE = """
scene_info = SceneInfo() { image_width = 96, image_height = 64, frames = 3 }
function scene(clock)
  local s = Scene() {
    background_color = Color(0.2, 0.25, 0.35),
    camera = Perspective(45, 96 / 64) { transform = LookAt(Vector(0, 1.5, -5), Vector(0, 0.3, 0), y) },
  }
  s:add_entity(Plane(Translate(Vector(0, -0.6, 0))))
  s:add_entity(Difference {
    Cube(Rotate(y, 30 + 60 * clock)),
    Sphere(Scale(0.65)),
    texture = Texture() { pigment = ColorPigment(COLOUR) },
  })
  s:add_light(Light() { transform = Translate(Vector(-3, 4, -3)) })
  return s
end
"""

RED, BLUE = "Color(0.9, 0.2, 0.1)", "Color(0.1, 0.3, 0.9)"
WATCH_SAMPLING = ["--noise-threshold", "0.01", "--min-samples", "4", "--max-samples", "256"]


def fail(message):
    print("browser_test: FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def write_scene(path, colour, extra=""):
    text = SCENE.replace("COLOUR", colour) + extra
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)  # as an editor saves


def page_pixels(driver):
    """The page's image drawn on a canvas: its RGBA bytes (base64)."""
    return driver.execute_script(
        """const img = document.getElementById('image');
           const c = document.createElement('canvas'); c.width = img.naturalWidth; c.height = img.naturalHeight;
           const g = c.getContext('2d'); g.drawImage(img, 0, 0);
           const d = g.getImageData(0, 0, c.width, c.height).data;
           let s = ''; for (let i = 0; i < d.length; i++) s += String.fromCharCode(d[i]);
           return btoa(s);""")


def file_pixels(driver, png_path):
    """A PNG file decoded by the same browser, as RGBA bytes (base64)."""
    data = base64.b64encode(open(png_path, "rb").read()).decode()
    return driver.execute_async_script(
        """const done = arguments[arguments.length - 1]; const img = new Image();
           img.onload = () => { const c = document.createElement('canvas'); c.width = img.width; c.height = img.height;
             const g = c.getContext('2d'); g.drawImage(img, 0, 0);
             const d = g.getImageData(0, 0, c.width, c.height).data;
             let s = ''; for (let i = 0; i < d.length; i++) s += String.fromCharCode(d[i]); done(btoa(s)); };
           img.onerror = () => done(null); img.src = 'data:image/png;base64,' + arguments[0];""", data)


def status(port):
    with urllib.request.urlopen("http://127.0.0.1:%d/status" % port, timeout=5) as r:
        return json.loads(r.read())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lray", required=True)
    ap.add_argument("--screenshot")
    ap.add_argument("--timeout", type=float, default=60)
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="lray_browser_")
    scene = os.path.join(work, "scene.lua")
    write_scene(scene, RED)
    port = free_port()
    log = open(os.path.join(work, "watch.log"), "w")
    watch = subprocess.Popen([args.lray, scene, os.path.join(work, "live"), "--watch", "-q",
                              "--serve=127.0.0.1:%d" % port], stdout=log, stderr=subprocess.STDOUT)
    driver = None
    try:
        deadline = time.time() + 20
        while True:  # the server answers (bounded)
            try:
                status(port)
                break
            except OSError:
                if watch.poll() is not None or time.time() > deadline:
                    fail("lray --watch did not serve its page: " + open(log.name).read())
                time.sleep(0.05)
        o = Options()
        for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=900,760"):
            o.add_argument(a)
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=o)
        driver.set_script_timeout(20)
        driver.get("http://127.0.0.1:%d/" % port)
        wait = WebDriverWait(driver, args.timeout, poll_frequency=0.05)

        def finished_image(_):
            """The page shows a finished render: its state, and the image of that version loaded."""
            st = driver.execute_script("return [document.body.dataset.state, document.getElementById('image').dataset.version]")
            s = status(port)
            return st[0] == "done" and s["state"] == "done" and st[1] == str(s["image_version"]) and s
        s1 = wait.until(finished_image, "the first image did not finish")

        # Its pixels are those of a direct render at the same sampling.
        direct = os.path.join(work, "direct")
        subprocess.run([args.lray, scene, direct, "-q", "--frames", "0"] + WATCH_SAMPLING, check=True)
        want = file_pixels(driver, os.path.join(direct, "scene0000.png"))
        got = page_pixels(driver)
        if not want or want != got:
            fail("the page's image differs from a direct render of the same scene and sampling")
        print("browser_test: first image matches the direct render (%d passes, %.1f spp, %.2f s)"
              % (s1["pass"], s1["samples_per_pixel"], s1["seconds"]))

        # An edit: a new colour shows within the bounded time.
        t0 = time.time()
        write_scene(scene, BLUE)
        s2 = wait.until(lambda d: (lambda s: s["image_version"] > s1["image_version"] and finished_image(d))(status(port)),
                        "the edited scene was not shown")
        blue = page_pixels(driver)
        if blue == got:
            fail("the picture did not change after the edit")
        subprocess.run([args.lray, scene, direct, "-q", "--frames", "0"] + WATCH_SAMPLING, check=True)
        if file_pixels(driver, os.path.join(direct, "scene0000.png")) != blue:
            fail("the re-rendered image differs from a direct render of the edited scene")
        print("browser_test: the edit showed after %.2f s" % (time.time() - t0))

        # A syntax error: file:line on the page, the last image kept.
        write_scene(scene, BLUE, "\nthis is not Lua\n")
        wait.until(lambda d: d.execute_script("return document.getElementById('error').style.display") == "block",
                   "the script error was not shown")
        message = driver.find_element("id", "error").text
        if "scene.lua:" not in message or ":" not in message.split("scene.lua:")[1]:
            fail("the error does not name file:line: " + message)
        if page_pixels(driver) != blue:
            fail("the last good image did not stay during the error")
        print("browser_test: error shown: " + message.splitlines()[0])
        # Fixed again.
        write_scene(scene, RED)
        wait.until(lambda d: d.execute_script("return document.getElementById('error').style.display") == "none"
                   and finished_image(d), "the fixed scene was not shown")
        if page_pixels(driver) != got:
            fail("after the fix the image differs from the first one")

        # The page's controls: another frame, the other backend.
        driver.execute_script("const f = document.getElementById('frame'); f.value = '2';"
                              "f.dispatchEvent(new Event('change'));")
        wait.until(lambda d: status(port)["frame"] == 2 and finished_image(d), "frame 2 was not shown")
        driver.execute_script("const b = document.getElementById('backend'); b.value = 'kdtree';"
                              "b.dispatchEvent(new Event('change'));")
        wait.until(lambda d: status(port)["backend"] == "kdtree" and finished_image(d), "the kd-tree render was not shown")
        subprocess.run([args.lray, scene, direct, "-q", "--frames", "2"] + WATCH_SAMPLING, check=True)
        if file_pixels(driver, os.path.join(direct, "scene0002.png")) != page_pixels(driver):
            fail("frame 2 on the kd-tree differs from a direct render")
        print("browser_test: frame slider and backend switch work")
        if args.screenshot:
            driver.save_screenshot(args.screenshot)
            print("browser_test: screenshot " + args.screenshot)
        # Ctrl-C ends it cleanly.
        watch.send_signal(signal.SIGINT)
        try:
            code = watch.wait(timeout=15)
        except subprocess.TimeoutExpired:
            fail("lray --watch did not stop on Ctrl-C")
        if code != 0:
            fail("lray --watch exited with %d on Ctrl-C" % code)
        print("browser_test: PASS")
    finally:
        if driver:
            driver.quit()
        if watch.poll() is None:
            watch.kill()
            watch.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
