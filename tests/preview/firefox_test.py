#!/usr/bin/python3
"""The live preview page in Firefox (issue 22): headless Firefox driven over
its own Marionette protocol (Debian has no geckodriver), so no package beyond
firefox-esr. Opens the page of `lray --watch --serve`, waits (bounded) for the
finished image, and checks its pixels against a direct render decoded by the
same browser; then an edit must show.

  firefox_test.py --lray build/lray
"""
import argparse
import base64
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

SCENE = """
scene_info = SceneInfo() { image_width = 80, image_height = 60 }
function scene(clock)
  local s = Scene() { camera = Perspective(45, 80 / 60) { transform = LookAt(Vector(0, 1.5, -5), Vector(0, 0.3, 0), y) } }
  s:add_entity(Plane(Translate(Vector(0, -0.6, 0))))
  s:add_entity(Intersection { Cube(Rotate(y, 30)), Sphere(Scale(0.7)), texture = Texture() { pigment = ColorPigment(COLOUR) } })
  s:add_light(Light() { transform = Translate(Vector(-3, 4, -3)) })
  return s
end
"""
SAMPLING = ["--noise-threshold", "0.01", "--min-samples", "4", "--max-samples", "256"]
PIXELS = """const i = arguments[0] ? null : document.getElementById('image');
  const done = arguments[arguments.length - 1];
  const draw = img => { const c = document.createElement('canvas'); c.width = img.naturalWidth; c.height = img.naturalHeight;
    const g = c.getContext('2d'); g.drawImage(img, 0, 0); const d = g.getImageData(0, 0, c.width, c.height).data;
    let s = ''; for (let k = 0; k < d.length; k++) s += String.fromCharCode(d[k]); done(btoa(s)); };
  if (i) draw(i); else { const img = new Image(); img.onload = () => draw(img); img.onerror = () => done(null);
    img.src = 'data:image/png;base64,' + arguments[0]; }"""


def fail(message):
    print("firefox_test: FAIL: " + message, file=sys.stderr)
    sys.exit(1)


class Marionette:
    def __init__(self, port):
        deadline = time.time() + 60
        while True:
            try:
                self.sock = socket.create_connection(("127.0.0.1", port), timeout=30)
                break
            except OSError:
                if time.time() > deadline:
                    fail("Firefox's Marionette port did not open")
                time.sleep(0.2)
        self.file = self.sock.makefile("rb")
        self.id = 0
        self.read()  # the server's hello

    def read(self):
        length = b""
        while not length.endswith(b":"):
            c = self.file.read(1)
            if not c:
                fail("Firefox closed the connection")
            length += c
        return json.loads(self.file.read(int(length[:-1])))

    def call(self, name, params=None):
        self.id += 1
        body = json.dumps([0, self.id, name, params or {}]).encode()
        self.sock.sendall(str(len(body)).encode() + b":" + body)
        reply = self.read()
        if reply[2]:
            fail("%s: %s" % (name, reply[2]))
        return reply[3]

    def run(self, script, *args, asynchronous=False):
        name = "WebDriver:ExecuteAsyncScript" if asynchronous else "WebDriver:ExecuteScript"
        return self.call(name, {"script": script, "args": list(args)})["value"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lray", required=True)
    ap.add_argument("--timeout", type=float, default=90)
    args = ap.parse_args()
    if not shutil.which("firefox-esr"):
        fail("firefox-esr is not installed (scripts/setup installs it)")
    work = tempfile.mkdtemp(prefix="lray_firefox_")
    scene = os.path.join(work, "scene.lua")
    with open(scene, "w") as f:
        f.write(SCENE.replace("COLOUR", "Color(0.9, 0.2, 0.1)"))
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        marionette_port = s.getsockname()[1]
    watch = subprocess.Popen([args.lray, scene, "--watch", "-q", "--serve=127.0.0.1:%d" % port],
                             stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
    profile = os.path.join(work, "profile")
    os.makedirs(profile)
    with open(os.path.join(profile, "user.js"), "w") as f:
        f.write('user_pref("marionette.port", %d);\n' % marionette_port)
    firefox = subprocess.Popen(["firefox-esr", "--headless", "--marionette", "--no-remote", "--profile", profile],
                               env=dict(os.environ, HOME=work), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        m = Marionette(marionette_port)
        m.call("WebDriver:NewSession", {"capabilities": {}})
        m.call("WebDriver:SetTimeouts", {"script": 20000})
        m.call("WebDriver:Navigate", {"url": "http://127.0.0.1:%d/" % port})

        def wait_done(after=0):
            deadline = time.time() + args.timeout
            while time.time() < deadline:
                v = m.run("const i = document.getElementById('image');"
                          "return [document.body.dataset.state, Number(i.dataset.version), i.complete && i.naturalWidth > 0];")
                status = json.loads(m.run("fetch('/status').then(r => r.text()).then(arguments[0]);",
                                          asynchronous=True))
                if v[0] == "done" and v[2] and v[1] == status["image_version"] and v[1] > after:
                    return v[1]
                time.sleep(0.1)
            fail("the page did not show a finished image in %.0f s" % args.timeout)

        first = wait_done()
        direct = os.path.join(work, "direct")
        subprocess.run([args.lray, scene, direct, "-q"] + SAMPLING, check=True)
        png = base64.b64encode(open(os.path.join(direct, "scene.png"), "rb").read()).decode()
        if m.run(PIXELS, None, asynchronous=True) != m.run(PIXELS, png, asynchronous=True):
            fail("the page's image differs from a direct render")
        with open(scene + ".tmp", "w") as f:
            f.write(SCENE.replace("COLOUR", "Color(0.1, 0.3, 0.9)"))
        os.replace(scene + ".tmp", scene)
        wait_done(first)
        subprocess.run([args.lray, scene, direct, "-q"] + SAMPLING, check=True)
        png = base64.b64encode(open(os.path.join(direct, "scene.png"), "rb").read()).decode()
        if m.run(PIXELS, None, asynchronous=True) != m.run(PIXELS, png, asynchronous=True):
            fail("after the edit the page's image differs from a direct render")
        agent = m.run("return navigator.userAgent;")
        print("firefox_test: PASS (%s)" % agent)
    finally:
        firefox.kill()
        firefox.wait()
        watch.kill()
        watch.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
