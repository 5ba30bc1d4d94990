// Pipeline: application (live preview). See preview_state.h.
#include "app/watch/preview_state.h"

#include <nlohmann/json.hpp>

namespace lray {

void PreviewState::publish(std::vector<uint8_t> png, const PreviewStatus &status,
                           const std::string &savePath) {
  auto image = std::make_shared<const std::vector<uint8_t>>(std::move(png));
  {
    std::lock_guard lock(mutex_);
    image_ = std::move(image);
    savePath_ = savePath;
    status_ = status;
    imageVersion_ = ++version_;
  }
  changed_.notify_all();
}

void PreviewState::publish(const PreviewStatus &status) {
  {
    std::lock_guard lock(mutex_);
    status_ = status;
    ++version_;
  }
  changed_.notify_all();
}

std::string PreviewState::statusJson() const {
  std::lock_guard lock(mutex_);
  const PreviewStatus &s = status_;
  nlohmann::json j = {{"version", version_},
                      {"has_image", image_ != nullptr},
                      {"image_version", imageVersion_},
                      {"state", s.state},
                      {"message", s.message},
                      {"pass", s.pass},
                      {"samples_per_pixel", s.samplesPerPixel},
                      {"seconds", s.seconds},
                      {"error_mean", s.errorMean},
                      {"error_max", s.errorMax},
                      {"frame", s.frame},
                      {"frames", s.frames},
                      {"clock", s.clock},
                      {"width", s.width},
                      {"height", s.height},
                      {"backend", s.backend},
                      {"backends", s.backends},
                      {"scene", s.scene}};
  nlohmann::json stats = nlohmann::json::parse(s.statsJson, nullptr, false);
  j["stats"] = stats.is_discarded() ? nlohmann::json() : stats;
  // A message or path that is not UTF-8 (a Latin-1 file name, a script's
  // error("caf\xe9")) is shown with replacement characters, never refused.
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::shared_ptr<const std::vector<uint8_t>> PreviewState::image() const {
  std::lock_guard lock(mutex_);
  return image_;
}

uint64_t PreviewState::version() const {
  std::lock_guard lock(mutex_);
  return version_;
}

uint64_t PreviewState::waitPast(uint64_t seen, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return version_ > seen || stopped_; });
  return version_;
}

void PreviewState::request(const PreviewRequest &r) {
  {
    std::lock_guard lock(mutex_);
    if (!request_) request_ = PreviewRequest{};
    if (r.frame) request_->frame = r.frame;
    if (r.backend) request_->backend = r.backend;
  }
  changed_.notify_all();
}

std::optional<PreviewRequest> PreviewState::takeRequest() {
  std::lock_guard lock(mutex_);
  std::optional<PreviewRequest> r = std::move(request_);
  request_.reset();
  return r;
}

bool PreviewState::requestPending() const {
  std::lock_guard lock(mutex_);
  return request_.has_value();
}

std::pair<std::shared_ptr<const std::vector<uint8_t>>, std::string>
PreviewState::imageToSave() const {
  std::lock_guard lock(mutex_);
  return {image_, savePath_};
}

void PreviewState::stop() {
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  changed_.notify_all();
}

bool PreviewState::stopped() const {
  std::lock_guard lock(mutex_);
  return stopped_;
}

} // namespace lray
