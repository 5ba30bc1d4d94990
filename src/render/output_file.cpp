// Pipeline: render (last stage). See output_file.h.
#include "render/output_file.h"

#include "util/scene_error.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

namespace lray {

namespace fs = std::filesystem;

namespace {

/// Writes all of `bytes` to `fd`; "" or the system's reason.
std::string writeAll(int fd, std::string_view bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return std::strerror(n < 0 ? errno : EIO);
    done += static_cast<size_t>(n);
  }
  return {};
}

/// A unique temporary name in `folder` for `finalPath`, keeping its
/// extension last (OpenImageIO picks the EXR writer from it).
fs::path temporaryBeside(const fs::path &folder, const fs::path &finalPath) {
  static std::atomic<unsigned> counter{0};
  return folder / ("." + finalPath.stem().string() + ".tmp" + std::to_string(getpid()) + "_" +
                   std::to_string(counter++) + finalPath.extension().string());
}

} // namespace

std::string writeWholeFile(const std::string &path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) return std::strerror(errno);
  std::string why = writeAll(fd, bytes);
  if (::close(fd) != 0 && why.empty()) why = std::strerror(errno);
  return why;
}

void writeAtomically(const std::string &path, const char *what,
                     const std::function<std::string(const std::string &tmp)> &write) {
  auto fail = [&](const std::string &why) {
    throw SceneError(std::string("cannot write ") + what + " '" + path + "': " + why);
  };
  // What is at the path, following symbolic links.
  fs::path target(path);
  std::error_code ec; // a missing path is a status, not an error, here
  const fs::file_status status = fs::status(target, ec);
  if (fs::is_symlink(fs::symlink_status(target, ec)) && fs::exists(status)) {
    target = fs::canonical(target, ec);
    if (ec) fail(ec.message());
  }
  if (fs::is_directory(status)) fail("a folder of that name is in the way");
  const bool replace = !fs::exists(status) || fs::is_regular_file(status);
  // A device or pipe is written through: the whole output is made in a
  // temporary file first (a failed render writes nothing to it).
  const fs::path folder = replace ? target.parent_path() : fs::temp_directory_path(ec);
  const fs::path tmp = temporaryBeside(folder.empty() ? fs::path(".") : folder, target);
  auto removeTmp = [&] {
    std::error_code ignored;
    fs::remove(tmp, ignored);
  };
  if (std::string why = write(tmp.string()); !why.empty()) {
    removeTmp();
    fail(why);
  }
  if (!fs::is_regular_file(tmp, ec)) fail("its writer reported success but wrote no file");
  if (replace) {
    fs::rename(tmp, target, ec);
    if (ec) {
      removeTmp();
      fail(ec.message());
    }
    return;
  }
  std::ifstream in(tmp, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  removeTmp();
  const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) fail(errno == ENXIO ? "a pipe with no reader" : std::strerror(errno));
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string why = writeAll(fd, bytes);
  if (::close(fd) != 0 && why.empty()) why = std::strerror(errno);
  if (!why.empty()) fail(why);
}

void writeOutputFile(const std::string &path, const char *what, std::string_view bytes) {
  writeAtomically(path, what, [&](const std::string &tmp) { return writeWholeFile(tmp, bytes); });
}

} // namespace lray
