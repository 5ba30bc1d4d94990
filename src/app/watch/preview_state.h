// Pipeline: application (live preview). What the watch loop publishes and
// the page's server reads: the current image (PNG), its status, and the
// page's requests (another frame or backend). Thread-safe; every change
// bumps a version that server-sent-event streams wait on.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace lray {

struct PreviewStatus {
  std::string state = "starting"; ///< starting, rendering, done or error
  std::string message;            ///< the script's error ("file:line: ..."), or empty
  int pass = 0;                   ///< 0: the quick first image; then the adaptive passes
  double samplesPerPixel = 0;
  double seconds = 0;             ///< since the render of this version of the scene began
  double errorMean = 0, errorMax = 0;
  int frame = 0, frames = 1;
  double clock = 0;
  int width = 0, height = 0;
  std::string backend;
  std::vector<std::string> backends;
  std::string statsJson = "{}"; ///< --stats of the last pass (run/render_stats.h)
  std::string scene;            ///< the scene file
};

/// A change the page asks for.
struct PreviewRequest {
  std::optional<int> frame;
  std::optional<std::string> backend;
};

class PreviewState {
public:
  /// A new image with its status (the image stays until the next one), and
  /// where the page's Save button writes it.
  void publish(std::vector<uint8_t> png, const PreviewStatus &status, const std::string &savePath);
  /// A new status, keeping the image (an error: the last good image stays).
  void publish(const PreviewStatus &status);

  /// The status as JSON, with "version" and "has_image".
  std::string statusJson() const;
  std::shared_ptr<const std::vector<uint8_t>> image() const;
  uint64_t version() const;
  /// Blocks until the version passes `seen`, `timeout` elapses or stop();
  /// returns the version then.
  uint64_t waitPast(uint64_t seen, std::chrono::milliseconds timeout) const;

  /// From the page; the watch loop takes it and renders again.
  void request(const PreviewRequest &r);
  std::optional<PreviewRequest> takeRequest();
  bool requestPending() const;

  /// The current image and the path the page's Save writes it to, together.
  std::pair<std::shared_ptr<const std::vector<uint8_t>>, std::string> imageToSave() const;

  void stop();
  bool stopped() const;

private:
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::shared_ptr<const std::vector<uint8_t>> image_;
  PreviewStatus status_;
  uint64_t version_ = 0;
  uint64_t imageVersion_ = 0; ///< the version that brought the current image
  std::optional<PreviewRequest> request_;
  std::string savePath_;
  bool stopped_ = false;
};

} // namespace lray
