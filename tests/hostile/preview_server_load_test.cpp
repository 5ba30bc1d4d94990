// The preview server under load (CTest label "hostile"): a real
// `lray --watch --serve` process against a bounded local client holding
// hundreds of idle, trickling and event-stream connections, oversized
// heads and bodies; every route must still be answered, the server's
// memory must stay small, and SIGINT must end it within a second.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace lray {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// A socket to 127.0.0.1:port, or -1.
int connectTo(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd >= 0 && connect(fd, reinterpret_cast<sockaddr *>(&a), sizeof a) == 0) return fd;
  if (fd >= 0) close(fd);
  return -1;
}

/// Sends what it can within `seconds` (false: the peer stopped reading or
/// closed, which is how a server refuses a body).
bool sendFor(int fd, const std::string &bytes, double seconds = 2) {
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  for (size_t sent = 0; sent < bytes.size();) {
    pollfd p{fd, POLLOUT, 0};
    if (Clock::now() > end || poll(&p, 1, 50) < 0) return false;
    if (!(p.revents & POLLOUT)) continue;
    const ssize_t n = send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return false;
    sent += size_t(n);
  }
  return true;
}

/// What arrives within `seconds`, until `until` is in it or the peer closes.
std::string receive(int fd, const std::string &until, double seconds) {
  std::string got;
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  char buf[65536];
  while (Clock::now() < end && got.find(until) == std::string::npos) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 20) <= 0) continue;
    const ssize_t n = read(fd, buf, sizeof buf); // a socket or a pipe
    if (n <= 0) break;
    got.append(buf, size_t(n));
  }
  return got;
}

/// The status line of one request on a connection of its own.
std::string ask(int port, const std::string &request, double seconds = 2) {
  const int fd = connectTo(port);
  if (fd < 0) return "no connection";
  sendFor(fd, request);
  const std::string answer = receive(fd, "\r\n", seconds);
  close(fd);
  return answer.substr(0, answer.find("\r\n"));
}

long residentKiB(pid_t pid, const char *field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field, 0) == 0) return std::stol(line.substr(line.find(':') + 1));
  return -1;
}

class HostileServer : public ::testing::Test {
protected:
  void SetUp() override {
    // The client's own descriptors: several hundred sockets.
    rlimit r{};
    getrlimit(RLIMIT_NOFILE, &r);
    r.rlim_cur = std::min<rlim_t>(r.rlim_max, 4096);
    setrlimit(RLIMIT_NOFILE, &r);
    dir_ = fs::temp_directory_path() / ("lray_hostile_server_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const fs::path scene = dir_ / "scene.lua";
    std::ofstream(scene)
        << "scene_info = SceneInfo() { image_width = 16, image_height = 16 }\n"
           "function scene()\n"
           "  local s = Scene() { camera = Perspective(45, 1) { transform = Translate(-4*z) } }\n"
           "  s:add_entity(Sphere())\n"
           "  s:add_light(Light() { transform = Translate(Vector(-3, 3, -3)) })\n"
           "  return s\n"
           "end\n";
    int out[2];
    ASSERT_EQ(pipe(out), 0);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(out[1], 1);
      dup2(out[1], 2);
      close(out[0]);
      close(out[1]);
      execl(LRAY_BINARY, LRAY_BINARY, "--watch", "--serve", "127.0.0.1:0", "-q", scene.c_str(),
            static_cast<char *>(nullptr));
      _exit(127);
    }
    close(out[1]);
    output_ = out[0];
    const std::string line = receive(output_, "\n", 20);
    const size_t at = line.find("127.0.0.1:");
    ASSERT_NE(at, std::string::npos) << line;
    port_ = std::stoi(line.substr(at + 10));
    host_ = "Host: 127.0.0.1:" + std::to_string(port_) + "\r\n";
  }
  void TearDown() override {
    for (int fd : held_)
      close(fd);
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (output_ >= 0) close(output_);
    fs::remove_all(dir_);
  }

  std::string get(const std::string &path) {
    return "GET " + path + " HTTP/1.1\r\n" + host_ + "\r\n";
  }
  int hold(const std::string &bytes = "") {
    const int fd = connectTo(port_);
    if (fd >= 0) {
      held_.push_back(fd);
      if (!bytes.empty()) sendFor(fd, bytes);
    }
    return fd;
  }

  fs::path dir_;
  pid_t pid_ = -1;
  int output_ = -1, port_ = 0;
  std::string host_;
  std::vector<int> held_;
};

TEST_F(HostileServer, EveryRouteIsAnsweredUnderLoadAndSigintEndsItWithinASecond) {
  ASSERT_EQ(ask(port_, get("/status")), "HTTP/1.1 200 OK");
  { // A client that shuts its side after its request is still answered.
    const int fd = connectTo(port_);
    sendFor(fd, get("/status"));
    shutdown(fd, SHUT_WR);
    EXPECT_EQ(receive(fd, "\r\n", 2).substr(0, 15), "HTTP/1.1 200 OK");
    close(fd);
  }
  // 32 event streams, each answered with its head and the first event.
  for (int i = 0; i < 32; ++i) {
    const int fd = hold(get("/events"));
    EXPECT_NE(receive(fd, "data: {", 2).find("data: {"), std::string::npos) << "stream " << i;
  }
  // 200 idle connections and 20 trickling a body a byte at a time.
  for (int i = 0; i < 200; ++i)
    hold();
  std::vector<int> tricklers;
  for (int i = 0; i < 20; ++i)
    tricklers.push_back(hold("POST /control HTTP/1.1\r\n" + host_ +
                             "Content-Length: 1000\r\nContent-Type: application/json\r\n\r\n{"));
  for (const char *route : {"/status", "/", "/image.png", "/nothing"}) {
    const auto t0 = Clock::now();
    const std::string status = ask(port_, get(route));
    EXPECT_EQ(status.rfind("HTTP/1.1 ", 0), 0u) << route << ": " << status;
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 1.0) << route;
  }
  // More connections than the server keeps: the oldest idle ones make
  // room, and requests are still answered.
  for (int i = 0; i < 400; ++i)
    hold();
  EXPECT_EQ(ask(port_, get("/status")), "HTTP/1.1 200 OK");
  // A 256 MiB head and a 512 MiB body are refused at their first bytes.
  {
    const int fd = connectTo(port_);
    std::string head = "GET /status HTTP/1.1\r\n" + host_;
    for (int i = 0; i < 4000; ++i)
      head += "X-Filler-" + std::to_string(i) + ": " + std::string(64, 'x') + "\r\n";
    EXPECT_FALSE(sendFor(fd, head + std::string(size_t{256} << 20, 'x'), 3));
    EXPECT_EQ(receive(fd, "\r\n", 2).substr(0, 12), "HTTP/1.1 431");
    close(fd);
  }
  {
    const int fd = connectTo(port_);
    const std::string head =
        "POST /control HTTP/1.1\r\n" + host_ + "Content-Length: 536870912\r\n\r\n";
    EXPECT_FALSE(sendFor(fd, head + std::string(size_t{512} << 20, ' '), 3));
    EXPECT_EQ(receive(fd, "\r\n", 2).substr(0, 12), "HTTP/1.1 413");
    close(fd);
  }
  EXPECT_EQ(ask(port_, get("/status")), "HTTP/1.1 200 OK");
  // Bounded: the whole episode costs the server little memory.
  const long peak = residentKiB(pid_, "VmHWM:");
  EXPECT_GT(peak, 0);
  EXPECT_LT(peak, 300 * 1024) << "peak resident KiB";
  // Still trickling: SIGINT ends the process within a second.
  for (int fd : tricklers)
    send(fd, " ", 1, MSG_NOSIGNAL);
  const auto t0 = Clock::now();
  kill(pid_, SIGINT);
  int status = 0;
  pid_t done = 0;
  while ((done = waitpid(pid_, &status, WNOHANG)) == 0 &&
         Clock::now() - t0 < std::chrono::seconds(5))
    usleep(5000);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  ASSERT_EQ(done, pid_) << "still running 5 s after SIGINT";
  pid_ = -1;
  EXPECT_LT(seconds, 1.0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

} // namespace
} // namespace lray
