#include "drivers/stereo/stereo_camera.h"

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
  depth_ = std::make_unique<StereoDepth>(
      o.calibration, nav::CameraMount(o.mount_x_m, o.mount_height_m, o.tilt_deg * std::numbers::pi / 180.0), o.depth);
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

void StereoCamera::Deliver(TimeNs stamp_ns, const cv::Mat& left, const cv::Mat& right) {
  auto frame = std::make_shared<RgbdFrame>();
  frame->stamp_ns = stamp_ns;
  frame->sequence = sequence_++;
  depth_->Process(left, right, *frame);
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
  const int frame_width = side_by_side ? 2 * o.width : o.width;
  std::vector<std::unique_ptr<V4l2Capture>> captures;
  for (const std::string& node : nodes) {
    captures.push_back(std::make_unique<V4l2Capture>(node, FourCcOf(o.format), frame_width, o.height, o.fps));
    if (captures.back()->width() != frame_width || captures.back()->height() != o.height) {
      throw std::runtime_error(fmt::format("{} streams {}x{}, not the configured {}x{}", node, captures.back()->width(),
                                           captures.back()->height(), frame_width, o.height));
    }
  }
  {
    std::lock_guard lock(mutex_);
    status_.nodes = side_by_side ? nodes[0] : nodes[0] + " + " + nodes[1];
  }
  FramePairer pairer(static_cast<TimeNs>(o.pair_tolerance_s * kNsPerSecond));
  TimeNs last_buffer_ns = clock_.Now();
  TimeNs last_pair_ns = last_buffer_ns;
  while (!stop.stop_requested()) {
    // One camera: wait for its frame. Two: take each one's newest in turn, waiting a little on each.
    const double wait_s = side_by_side ? o.stale_s / 2.0 : std::min(0.005, o.stale_s / 4.0);
    for (std::size_t i = 0; i < captures.size(); ++i) {
      const std::optional<V4l2Capture::Buffer> b = captures[i]->Next(wait_s);
      if (!b) continue;
      const TimeNs now = clock_.Now();
      last_buffer_ns = now;
      cv::Mat image;
      try {
        image = DecodeBuffer(b->bytes, o.format, frame_width, o.height, captures[i]->stride());
      } catch (const std::invalid_argument&) {
        std::lock_guard lock(mutex_);
        ++status_.bad_frames;
        continue;
      }
      if (side_by_side) {
        cv::Mat left;
        cv::Mat right;
        SplitSideBySide(image, left, right);
        Deliver(now, left, right);
        last_pair_ns = now;
      } else {
        // The driver's time stamps (one clock for both cameras) pair the frames; the host's clock stamps the pair.
        if (i == 0) {
          pairer.PushLeft(b->stamp_ns, std::move(image));
        } else {
          pairer.PushRight(b->stamp_ns, std::move(image));
        }
        if (std::optional<FramePairer::Pair> pair = pairer.Take()) {
          Deliver(now, pair->left, pair->right);
          last_pair_ns = now;
        }
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
