// The live preview's parts (app/watch/): change detection (debounced, by
// name in the watched folders, replacements by rename), the files a scene
// read, cancelling a render within one pass, and the page server's request
// handling (unknown paths, traversal, other origins and hosts).
#include "app/watch/file_watcher.h"
#include "app/watch/preview_server.h"
#include "app/watch/preview_state.h"
#include "bindings/scene_script.h"
#include "render/renderer.h"
#include "shading/image_cache.h"
#include "render/backends.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace lray {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

class WatchTest : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("lray_watch_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string &name, const std::string &text) {
    std::ofstream(dir_ / name) << text;
  }
  fs::path dir_;
};

TEST_F(WatchTest, ChangesToWatchedFilesAreSeenOnceAndOthersIgnored) {
  write("scene.lua", "a");
  write("other.txt", "b");
  FileWatcher w;
  w.watch({(dir_ / "scene.lua").string()});
  EXPECT_FALSE(w.waitForChange(milliseconds(100), milliseconds(50)));
  write("other.txt", "c"); // same folder, not watched
  EXPECT_FALSE(w.waitForChange(milliseconds(100), milliseconds(50)));
  // Three writes in quick succession: one change after the debounce.
  std::thread editor([&] {
    for (int i = 0; i < 3; ++i) {
      write("scene.lua", std::to_string(i));
      std::this_thread::sleep_for(milliseconds(20));
    }
  });
  EXPECT_TRUE(w.waitForChange(milliseconds(2000), milliseconds(100)));
  editor.join();
  EXPECT_FALSE(w.waitForChange(milliseconds(150), milliseconds(50)));
  // An editor's save by renaming a new file over the old one.
  write("scene.lua.new", "d");
  fs::rename(dir_ / "scene.lua.new", dir_ / "scene.lua");
  EXPECT_TRUE(w.waitForChange(milliseconds(2000), milliseconds(50)));
  // Deleted, then created again.
  fs::remove(dir_ / "scene.lua");
  EXPECT_TRUE(w.waitForChange(milliseconds(2000), milliseconds(50)));
  // Watching another set drops the old one.
  write("mesh.obj", "v 0 0 0\n");
  EXPECT_FALSE(w.waitForChange(milliseconds(100), milliseconds(50))); // not watched yet
  w.watch({(dir_ / "mesh.obj").string()});
  write("scene.lua", "e");
  EXPECT_FALSE(w.waitForChange(milliseconds(150), milliseconds(50)));
  write("mesh.obj", "v 1 0 0\n");
  EXPECT_TRUE(w.waitForChange(milliseconds(2000), milliseconds(50)));
}

TEST_F(WatchTest, TheScriptReportsEveryFileItRead) {
  write("part.lua", "size = 0.5\n");
  write("data.txt", "3\n");
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write("scene.lua", "dofile('part.lua')\nlocal f = io.open('data.txt') ; f:read('a') ; f:close()\n"
                     "local m = mesh_from_obj('tri.obj')\n"
                     "function scene() local s = Scene() ; s:add_entity(m) ; return s end\n");
  SceneScript script((dir_ / "scene.lua").string());
  std::vector<std::string> read = script.filesRead();
  ASSERT_EQ(read.size(), 3u);
  EXPECT_EQ(fs::path(read[0]).filename(), "part.lua");
  EXPECT_EQ(fs::path(read[1]).filename(), "data.txt");
  EXPECT_EQ(fs::path(read[2]).filename(), "tri.obj");
}

TEST_F(WatchTest, FilesReadBeforeALoadFailsAreReported) {
  // An included file with a syntax error: watched, so that fixing it renders again.
  write("part.lua", "this is not Lua\n");
  write("scene.lua", "dofile('part.lua')\nfunction scene() return Scene() end\n");
  ScriptOptions options;
  options.readLog = std::make_shared<std::vector<std::string>>();
  EXPECT_THROW(SceneScript((dir_ / "scene.lua").string(), options), SceneError);
  ASSERT_EQ(options.readLog->size(), 1u);
  EXPECT_EQ(fs::path(options.readLog->front()).filename(), "part.lua");
}

TEST_F(WatchTest, ALoadErrorCarriesTheFilesRead) {
  // What the watch loop watches after a failed load, with no list of its own.
  write("part.lua", "this is not Lua\n");
  write("scene.lua", "dofile('part.lua')\nfunction scene() return Scene() end\n");
  try {
    SceneScript script((dir_ / "scene.lua").string());
    FAIL() << "the script loaded";
  } catch (const ScriptLoadError &e) {
    ASSERT_EQ(e.filesRead.size(), 1u);
    EXPECT_EQ(fs::path(e.filesRead.front()).filename(), "part.lua");
  }
}

TEST(PreviewStateTest, TextThatIsNotUtf8IsShownNotRefused) {
  PreviewState state;
  PreviewStatus st;
  st.message = "scene.lua:3: caf\xe9";
  st.scene = "/tmp/\xff.lua";
  st.statsJson = "{\"file\": \"\xe9\"}";
  state.publish(st);
  std::string json;
  ASSERT_NO_THROW(json = state.statusJson());
  EXPECT_NE(json.find("caf\xef\xbf\xbd"), std::string::npos) << json; // U+FFFD
}

TEST_F(WatchTest, ACancelledRenderStopsWithinOnePass) {
  write("scene.lua",
        "function scene() local s = Scene() ; s:add_entity(Sphere(Translate(Vector(0, 0, 4))))\n"
        "s:add_light(Light() { transform = Translate(Vector(2, 3, 0)) }) ; return s end\n");
  SceneScript script((dir_ / "scene.lua").string());
  Scene scene = script.buildFrame(0);
  auto accel = makeAccelerator(BackendKind::Embree, scene);
  ImageCache images(false);
  FrameSettings s;
  s.width = 48;
  s.height = 32;
  s.adaptive = true;
  s.adaptiveSettings = {1e-9, 4, 4096, 0}; // would take many passes
  std::atomic<bool> cancel{false};
  s.cancel = &cancel;
  int passesSeen = 0;
  s.onPass = [&](const Film &film) {
    ++passesSeen;
    EXPECT_EQ(film.report.passes, passesSeen);
    if (passesSeen == 2) cancel = true; // an edit arrives during pass 3
  };
  RayCounts counts;
  Film film = renderFrame(scene, *accel, images, s, counts);
  EXPECT_TRUE(film.report.cancelled);
  EXPECT_EQ(passesSeen, 2);
  EXPECT_LE(film.report.passes, 3);
  EXPECT_LT(film.report.maxPixelSamples, 4096u);
}

TEST(PreviewServer, ServesOnlyItsRoutesToItsOwnOrigin) {
  PreviewState state;
  PreviewServer server(state, "127.0.0.1", 0);
  ASSERT_GT(server.port(), 0);
  httplib::Client client("127.0.0.1", server.port());
  const std::string origin = "http://127.0.0.1:" + std::to_string(server.port());
  auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("EventSource(\"/events\")"), std::string::npos);
  EXPECT_EQ(page->body.find("http"), page->body.find("http-equiv")); // no external asset
  EXPECT_EQ(client.Get("/image.png")->status, 404); // no image yet
  PreviewStatus st;
  st.state = "done";
  state.publish({0x89, 'P', 'N', 'G'}, st, "");
  auto image = client.Get("/image.png");
  EXPECT_EQ(image->status, 200);
  EXPECT_EQ(image->body, std::string("\x89PNG"));
  EXPECT_EQ(image->get_header_value("Content-Type"), "image/png");
  for (const char *path : {"/nothing", "/../../etc/passwd", "/image.png/../../etc/passwd",
                           "/%2e%2e/%2e%2e/etc/passwd", "//etc/passwd", "/scene.lua"})
    EXPECT_EQ(client.Get(path)->status, 404) << path;
  auto status = client.Get("/status");
  EXPECT_NE(status->body.find("\"state\":\"done\""), std::string::npos) << status->body;
  // Other origins: no event stream, no actions.
  httplib::Headers evil = {{"Origin", "http://evil.example"}};
  EXPECT_EQ(client.Get("/events", evil)->status, 403);
  EXPECT_EQ(client.Post("/control", evil, "{\"frame\": 3}", "application/json")->status, 403);
  EXPECT_EQ(client.Post("/save", evil, "{}", "application/json")->status, 403);
  EXPECT_FALSE(state.requestPending());
  // Another Host (DNS rebinding): refused everywhere.
  EXPECT_EQ(client.Get("/", {{"Host", "evil.example:" + std::to_string(server.port())}})->status,
            403);
  // The page's own origin: accepted; malformed requests: 400.
  httplib::Headers own = {{"Origin", origin}};
  EXPECT_EQ(
      client.Post("/control", own, "{\"frame\": 3, \"backend\": \"kdtree\"}", "application/json")
          ->status,
      204);
  auto r = state.takeRequest();
  ASSERT_TRUE(r);
  EXPECT_EQ(*r->frame, 3);
  EXPECT_EQ(*r->backend, "kdtree");
  EXPECT_EQ(client.Post("/control", own, "not json", "application/json")->status, 400);
  EXPECT_EQ(client.Post("/control", own, "{\"frame\": -1}", "application/json")->status, 400);
  EXPECT_EQ(client.Post("/save", own, "{}", "application/json")->status, 409); // no save path
  // The event stream starts with the current status.
  std::string events;
  client.set_read_timeout(2, 0);
  client.Get("/events", own, [&](const char *data, size_t n) {
    events.append(data, n);
    return events.find("\n\n") == std::string::npos;
  });
  EXPECT_EQ(events.rfind("data: {", 0), 0u) << events;
  // A body larger than any the page sends is refused before it is read.
  EXPECT_EQ(client.Post("/control", own, std::string(1 << 20, ' '), "application/json")->status,
            413);
  server.stop();
}

TEST(PreviewServer, OnALoopbackAliasAForeignHostIsRefused) {
  for (const std::string host : {"127.0.0.2", "127.1"}) {
    SCOPED_TRACE(host);
    PreviewState state;
    PreviewServer server(state, host, 0);
    ASSERT_GT(server.port(), 0);
    httplib::Client client(host == "127.1" ? "127.0.0.1" : host, server.port());
    const std::string port = ":" + std::to_string(server.port());
    auto foreign = client.Get("/", {{"Host", "evil.example" + port}});
    ASSERT_TRUE(foreign);
    EXPECT_EQ(foreign->status, 403);
    EXPECT_EQ(client.Get("/status", {{"Host", host + port}})->status, 200);
    EXPECT_EQ(client.Get("/status", {{"Host", "localhost" + port}})->status, 200);
    server.stop();
  }
}

} // namespace
} // namespace lray
