#include "drivers/realsense/realsense_camera.h"

#include <memory>
#include <stdexcept>

#include <spdlog/fmt/fmt.h>

#include "drivers/realsense/v4l2_capture.h"

namespace corridor::drivers::realsense {

RealSenseCamera::RealSenseCamera(const RealSenseOptions& options, const Clock& clock)
    : LinkedDevice("realsense", options.depth_node.empty() ? options.name : options.depth_node),
      options_(options),
      clock_(clock) {
  const CameraMountOptions& c = options.camera;
  if (!Usable(c) || !(options.depth_scale_m > 0.0) || !(options.stale_s > 0.0) ||
      !(options.silence_s > options.stale_s) || !(options.reconnect_s > 0.0)) {
    throw std::invalid_argument(
        "realsense: size, rate, depth unit and timeouts must be positive, intrinsics given or fields of view within "
        "0-180 degrees, and silence_s longer than stale_s");
  }
  info_.camera = ToPinhole(c);
  info_.min_range_m = c.min_range_m;
  info_.max_range_m = c.max_range_m;
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

RealSenseCamera::~RealSenseCamera() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void RealSenseCamera::SetFrameHandler(FrameHandler handler) {
  std::lock_guard lock(mutex_);
  handler_ = std::move(handler);
}

void RealSenseCamera::Run(std::stop_token stop) {
  RunSessions(stop, options_.reconnect_s, [&] { Session(stop); });
}

void RealSenseCamera::Session(std::stop_token stop) {
  SetState(LinkState::kConnecting);
  NodePair nodes{options_.depth_node, options_.color_node};
  if (nodes.depth.empty()) {
    const std::optional<NodePair> found = PickNodes(ListVideoNodes(), options_.name);
    if (!found) {
      throw std::runtime_error(
          fmt::format("no video node of a device named '{}' offers Z16 depth (plugged in?)", options_.name));
    }
    nodes.depth = found->depth;
    if (nodes.color.empty()) nodes.color = found->color;
  }
  V4l2Capture depth(nodes.depth, kZ16, options_.camera.width, options_.camera.height, options_.camera.fps);
  if (depth.width() != options_.camera.width || depth.height() != options_.camera.height) {
    throw std::runtime_error(fmt::format("{} streams depth at {}x{}, not the configured {}x{}", nodes.depth,
                                         depth.width(), depth.height(), options_.camera.width, options_.camera.height));
  }
  std::unique_ptr<V4l2Capture> color;
  if (!nodes.color.empty() && nodes.color != "none") {
    color = std::make_unique<V4l2Capture>(nodes.color, kYuyv, options_.camera.width, options_.camera.height,
                                          options_.camera.fps);
  }
  {
    std::lock_guard lock(mutex_);
    status_.depth_node = nodes.depth;
    status_.color_node = color ? nodes.color : "";
  }
  cv::Mat latest_color(options_.camera.height, options_.camera.width, CV_8UC3, cv::Scalar::all(0));
  TimeNs last_frame_ns = clock_.Now();
  std::uint64_t sequence = 0;
  while (!stop.stop_requested()) {
    if (color) {
      // The newest colour frame, if one is waiting.
      while (const std::optional<V4l2Capture::Buffer> c = color->Next(0.0)) {
        latest_color =
            YuyvToBgr(c->bytes, color->width(), color->height(), color->stride(), depth.width(), depth.height());
      }
    }
    const std::optional<V4l2Capture::Buffer> d = depth.Next(options_.stale_s / 2.0);
    const TimeNs now = clock_.Now();
    if (!d) {
      const double quiet_s = ToSeconds(now - last_frame_ns);
      if (quiet_s >= options_.silence_s) {
        SetState(LinkState::kSilent,
                 fmt::format("no depth frame for {:.1f} s: opening the camera anew", options_.silence_s));
        return;
      }
      if (quiet_s >= options_.stale_s) {
        SetState(LinkState::kStale, fmt::format("no depth frame for {:.0f} ms", options_.stale_s * 1e3));
      }
      continue;
    }
    last_frame_ns = now;
    auto frame = std::make_shared<RgbdFrame>();
    frame->stamp_ns = now;
    frame->sequence = sequence++;
    frame->depth_mm =
        DepthToMillimetres(d->bytes, depth.width(), depth.height(), depth.stride(), options_.depth_scale_m);
    frame->color_bgr = latest_color.size() == frame->depth_mm.size()
                           ? latest_color.clone()
                           : cv::Mat(frame->depth_mm.size(), CV_8UC3, cv::Scalar::all(0));
    FrameHandler handler;
    {
      std::lock_guard lock(mutex_);
      ++status_.frames;
      handler = handler_;
    }
    SetState(LinkState::kRunning);
    if (handler) handler(std::move(frame));
  }
}

}  // namespace corridor::drivers::realsense
