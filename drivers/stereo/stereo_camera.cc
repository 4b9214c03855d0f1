#include "drivers/stereo/stereo_camera.h"

#include <algorithm>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <vector>

#include <spdlog/fmt/fmt.h>

#include "drivers/realsense/v4l2_capture.h"

namespace corridor::drivers::stereo {
namespace {

using realsense::V4l2Capture;

const char* Name(VideoFormat format) { return format == VideoFormat::kMjpeg ? "MJPEG" : "YUYV"; }

}  // namespace

StereoCamera::StereoCamera(const StereoCameraOptions& options, const Clock& clock)
    : LinkedDevice("stereo", Where(options)), options_(options), clock_(clock) {
  const StereoCameraOptions& o = options;
  if (o.width <= 0 || o.height <= 0 || o.fps <= 0 || !(o.stale_s > 0.0) || !(o.silence_s > o.stale_s) ||
      !(o.reconnect_s > 0.0) || !(o.pair_tolerance_s > 0.0)) {
    throw std::invalid_argument("stereo: size, rate and timeouts must be positive and silence_s longer than stale_s");
  }
  if (o.calibration.image_size != cv::Size(o.width, o.height)) {
    throw std::invalid_argument(fmt::format("stereo: the calibration is of {} x {} px views, the camera's are {} x {}",
                                            o.calibration.image_size.width, o.calibration.image_size.height, o.width,
                                            o.height));
  }
  if (o.layout == StereoLayout::kTwoCameras && (o.left_node.empty() || o.right_node.empty())) {
    throw std::invalid_argument("stereo: two cameras need left_node and right_node");
  }
  if (o.third_node.empty() != !o.wide_calibration) {
    throw std::invalid_argument("stereo: a third camera needs both its node and the wide pair's calibration");
  }
  depth_ = std::make_unique<MultiBaselineDepth>(
      o.calibration, o.wide_calibration,
      nav::CameraMount(o.mount_x_m, o.mount_height_m, o.tilt_deg * std::numbers::pi / 180.0), o.depth,
      o.wide_disparities, o.fusion);
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

StereoCamera::~StereoCamera() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void StereoCamera::SetFrameHandler(FrameHandler handler) {
  std::lock_guard lock(mutex_);
  handler_ = std::move(handler);
}

void StereoCamera::Run(std::stop_token stop) {
  RunSessions(stop, options_.reconnect_s, [&] { Session(stop); });
}

void StereoCamera::Deliver(TimeNs stamp_ns, const cv::Mat& left, const cv::Mat& right, const cv::Mat& third) {
  auto frame = std::make_shared<RgbdFrame>();
  frame->stamp_ns = stamp_ns;
  frame->sequence = sequence_++;
  depth_->Process(left, right, third, *frame);
  FrameHandler handler;
  {
    std::lock_guard lock(mutex_);
    ++status_.frames;
    handler = handler_;
  }
  SetState(LinkState::kRunning);
  if (handler) handler(std::move(frame));
}

void StereoCamera::Session(std::stop_token stop) {
  SetState(LinkState::kConnecting);
  const StereoCameraOptions& o = options_;
  const bool side_by_side = o.layout == StereoLayout::kSideBySide;
  std::vector<std::string> nodes;
  if (side_by_side) {
    std::optional<std::string> node = o.node.empty() ? std::nullopt : std::optional<std::string>(o.node);
    if (!node) node = PickStereoNode(realsense::ListVideoNodes(), o.name, o.format);
    if (!node) {
      throw std::runtime_error(
          fmt::format("no video node of a device named '{}' offers {} (plugged in?)", o.name, Name(o.format)));
    }
    nodes.push_back(*node);
  } else {
    nodes = {o.left_node, o.right_node};
  }
  if (!o.third_node.empty()) nodes.push_back(o.third_node);
  std::vector<std::unique_ptr<V4l2Capture>> captures;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const int width = side_by_side && i == 0 ? 2 * o.width : o.width;  // a side-by-side frame holds both views
    captures.push_back(std::make_unique<V4l2Capture>(nodes[i], FourCcOf(o.format), width, o.height, o.fps));
    if (captures.back()->width() != width || captures.back()->height() != o.height) {
      throw std::runtime_error(fmt::format("{} streams {}x{}, not the configured {}x{}", nodes[i],
                                           captures.back()->width(), captures.back()->height(), width, o.height));
    }
  }
  {
    std::lock_guard lock(mutex_);
    status_.nodes = nodes[0];
    for (std::size_t i = 1; i < nodes.size(); ++i) status_.nodes += " + " + nodes[i];
  }
  // One node alone (a side-by-side camera without a third) delivers each frame; several are joined by time stamps.
  const bool one_node = nodes.size() == 1;
  FrameSet set(std::max(2, static_cast<int>(nodes.size())), static_cast<TimeNs>(o.pair_tolerance_s * kNsPerSecond));
  const auto deliver = [&](TimeNs now, std::vector<cv::Mat>& images) {
    cv::Mat left, right;
    if (side_by_side) {
      SplitSideBySide(images[0], left, right);
    } else {
      left = images[0];
      right = images[1];
    }
    Deliver(now, left, right, o.third_node.empty() ? cv::Mat() : images.back());
  };
  TimeNs last_buffer_ns = clock_.Now();
  TimeNs last_pair_ns = last_buffer_ns;
  while (!stop.stop_requested()) {
    // One node: wait for its frame. Several: take each one's newest in turn, waiting a little on each.
    const double wait_s = one_node ? o.stale_s / 2.0 : std::min(0.005, o.stale_s / 4.0);
    for (std::size_t i = 0; i < captures.size(); ++i) {
      const std::optional<V4l2Capture::Buffer> b = captures[i]->Next(wait_s);
      if (!b) continue;
      const TimeNs now = clock_.Now();
      last_buffer_ns = now;
      cv::Mat image;
      try {
        image = DecodeBuffer(b->bytes, o.format, captures[i]->width(), o.height, captures[i]->stride());
      } catch (const std::invalid_argument&) {
        std::lock_guard lock(mutex_);
        ++status_.bad_frames;
        continue;
      }
      if (one_node) {
        std::vector<cv::Mat> images{std::move(image)};
        deliver(now, images);
        last_pair_ns = now;
        continue;
      }
      // The driver's time stamps (one clock for every camera) join the frames; the host's clock stamps the set.
      set.Push(static_cast<int>(i), b->stamp_ns, std::move(image));
      if (std::optional<FrameSet::Set> taken = set.Take()) {
        deliver(now, taken->images);
        last_pair_ns = now;
      }
    }
    const TimeNs now = clock_.Now();
    if (ToSeconds(now - last_buffer_ns) >= o.silence_s) {
      SetState(LinkState::kSilent, fmt::format("no frame for {:.1f} s: opening the camera anew", o.silence_s));
      return;
    }
    if (ToSeconds(now - last_pair_ns) >= o.stale_s) {
      SetState(LinkState::kStale, fmt::format("no depth frame for {:.0f} ms", o.stale_s * 1e3));
    }
  }
}

}  // namespace corridor::drivers::stereo
