#include "drivers/stereo/stereo_frames.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include <opencv2/imgcodecs.hpp>

namespace corridor::drivers::stereo {

std::uint32_t FourCcOf(VideoFormat format) { return format == VideoFormat::kMjpeg ? kMjpg : realsense::kYuyv; }

cv::Mat DecodeBuffer(std::span<const std::uint8_t> bytes, VideoFormat format, int width, int height, int stride) {
  if (format == VideoFormat::kYuyv) return realsense::YuyvToBgr(bytes, width, height, stride, width, height);
  // A JPEG starts with its SOI marker; a torn or empty buffer is refused before the decoder sees it.
  if (bytes.size() < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8) {
    throw std::invalid_argument("an MJPEG buffer that is not a JPEG (" + std::to_string(bytes.size()) + " bytes)");
  }
  // A torn frame (the bus dropped its end) lacks the EOI marker; some cameras pad after it.
  const std::size_t tail = std::min<std::size_t>(bytes.size(), 64);
  bool ended = false;
  for (std::size_t i = bytes.size() - tail; i + 1 < bytes.size(); ++i)
    ended = ended || (bytes[i] == 0xFF && bytes[i + 1] == 0xD9);
  if (!ended) throw std::invalid_argument("a torn MJPEG frame (no end marker)");
  cv::Mat image;
  try {
    const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<std::uint8_t*>(bytes.data()));
    image = cv::imdecode(raw, cv::IMREAD_COLOR);
  } catch (const cv::Exception&) {
    image.release();
  }
  if (image.empty()) throw std::invalid_argument("an MJPEG frame that does not decode");
  if (image.cols != width || image.rows != height) {
    throw std::invalid_argument("an MJPEG frame of " + std::to_string(image.cols) + " x " + std::to_string(image.rows) +
                                " px, not " + std::to_string(width) + " x " + std::to_string(height));
  }
  return image;
}

std::optional<std::string> PickStereoNode(const std::vector<realsense::VideoNode>& nodes, const std::string& name,
                                          VideoFormat format) {
  std::optional<std::string> best;
  const std::uint32_t fourcc = FourCcOf(format);
  for (const realsense::VideoNode& node : nodes) {
    if (node.card.find(name) == std::string::npos) continue;
    if (std::find(node.formats.begin(), node.formats.end(), fourcc) == node.formats.end()) continue;
    // /dev/video2 before /dev/video10.
    if (!best || node.path.size() < best->size() || (node.path.size() == best->size() && node.path < *best)) {
      best = node.path;
    }
  }
  return best;
}

void SplitSideBySide(const cv::Mat& frame, cv::Mat& left, cv::Mat& right) {
  if (frame.empty() || frame.cols % 2 != 0) {
    throw std::invalid_argument("a side-by-side frame needs an even width, got " + std::to_string(frame.cols));
  }
  left = frame.colRange(0, frame.cols / 2);
  right = frame.colRange(frame.cols / 2, frame.cols);
}

FrameSet::FrameSet(int cameras, TimeNs tolerance_ns) : tolerance_ns_(tolerance_ns) {
  if (cameras < 2) throw std::invalid_argument("a frame set needs two cameras or more");
  newest_.resize(static_cast<std::size_t>(cameras));
}

void FrameSet::Push(int camera, TimeNs stamp_ns, cv::Mat image) {
  newest_.at(static_cast<std::size_t>(camera)) = Frame{stamp_ns, std::move(image)};
}

std::optional<FrameSet::Set> FrameSet::Take() {
  TimeNs oldest = std::numeric_limits<TimeNs>::max();
  TimeNs newest = std::numeric_limits<TimeNs>::min();
  for (const std::optional<Frame>& f : newest_) {
    if (!f) return std::nullopt;
    oldest = std::min(oldest, f->stamp_ns);
    newest = std::max(newest, f->stamp_ns);
  }
  if (newest - oldest > tolerance_ns_) return std::nullopt;
  Set set{oldest, {}};
  for (std::optional<Frame>& f : newest_) {
    set.images.push_back(std::move(f->image));
    f.reset();
  }
  return set;
}

}  // namespace corridor::drivers::stereo
