#include "drivers/realsense/v4l2_capture.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace corridor::drivers::realsense {
namespace {

constexpr int kBuffers = 4;

// ioctl, again when a signal interrupted it.
int Ioctl(int fd, unsigned long request, void* argument) {
  int result;
  do {
    result = ::ioctl(fd, request, argument);
  } while (result == -1 && errno == EINTR);
  return result;
}

[[noreturn]] void Fail(const std::string& path, const char* what) {
  throw std::runtime_error(path + ": " + what + ": " + std::strerror(errno));
}

}  // namespace

std::vector<VideoNode> ListVideoNodes() {
  std::vector<VideoNode> nodes;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/dev", ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("video")) continue;
    const int fd = ::open(entry.path().c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    v4l2_capability caps{};
    if (Ioctl(fd, VIDIOC_QUERYCAP, &caps) == 0 && (caps.device_caps & V4L2_CAP_VIDEO_CAPTURE)) {
      VideoNode node{entry.path().string(), reinterpret_cast<const char*>(caps.card), {}};
      v4l2_fmtdesc format{};
      format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      for (format.index = 0; Ioctl(fd, VIDIOC_ENUM_FMT, &format) == 0; ++format.index) {
        node.formats.push_back(format.pixelformat);
      }
      nodes.push_back(std::move(node));
    }
    ::close(fd);
  }
  return nodes;
}

V4l2Capture::V4l2Capture(const std::string& path, std::uint32_t format, int width, int height, int fps) {
  fd_ = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) Fail(path, "opening");
  try {
    v4l2_format f{};
    f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    f.fmt.pix.width = static_cast<std::uint32_t>(width);
    f.fmt.pix.height = static_cast<std::uint32_t>(height);
    f.fmt.pix.pixelformat = format;
    f.fmt.pix.field = V4L2_FIELD_NONE;
    if (Ioctl(fd_, VIDIOC_S_FMT, &f) != 0) Fail(path, "setting the format");
    if (f.fmt.pix.pixelformat != format) {
      errno = EINVAL;
      Fail(path, "the format asked for is not offered");
    }
    width_ = static_cast<int>(f.fmt.pix.width);
    height_ = static_cast<int>(f.fmt.pix.height);
    stride_ = static_cast<int>(f.fmt.pix.bytesperline);
    v4l2_streamparm rate{};
    rate.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    rate.parm.capture.timeperframe = {1, static_cast<std::uint32_t>(fps)};
    Ioctl(fd_, VIDIOC_S_PARM, &rate);  // a node without rates keeps its own
    v4l2_requestbuffers request{};
    request.count = kBuffers;
    request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    request.memory = V4L2_MEMORY_MMAP;
    if (Ioctl(fd_, VIDIOC_REQBUFS, &request) != 0 || request.count == 0) Fail(path, "asking for buffers");
    for (std::uint32_t i = 0; i < request.count; ++i) {
      v4l2_buffer b{};
      b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      b.memory = V4L2_MEMORY_MMAP;
      b.index = i;
      if (Ioctl(fd_, VIDIOC_QUERYBUF, &b) != 0) Fail(path, "querying a buffer");
      void* memory = ::mmap(nullptr, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, b.m.offset);
      if (memory == MAP_FAILED) Fail(path, "mapping a buffer");
      buffers_.emplace_back(static_cast<std::uint8_t*>(memory), b.length);
      if (Ioctl(fd_, VIDIOC_QBUF, &b) != 0) Fail(path, "queueing a buffer");
    }
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (Ioctl(fd_, VIDIOC_STREAMON, &type) != 0) Fail(path, "starting the stream");
  } catch (...) {
    for (const auto& b : buffers_) ::munmap(b.data(), b.size());
    ::close(fd_);
    throw;
  }
}

V4l2Capture::~V4l2Capture() {
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  Ioctl(fd_, VIDIOC_STREAMOFF, &type);
  for (const auto& b : buffers_) ::munmap(b.data(), b.size());
  ::close(fd_);
}

void V4l2Capture::Requeue() {
  if (lent_ < 0) return;
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  b.index = static_cast<std::uint32_t>(lent_);
  lent_ = -1;
  if (Ioctl(fd_, VIDIOC_QBUF, &b) != 0)
    throw std::runtime_error(std::string("queueing a buffer: ") + std::strerror(errno));
}

std::optional<V4l2Capture::Buffer> V4l2Capture::Next(double timeout_s) {
  Requeue();
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, static_cast<int>(timeout_s * 1000.0));
  if (ready < 0 && errno != EINTR)
    throw std::runtime_error(std::string("waiting for a frame: ") + std::strerror(errno));
  if (ready <= 0) return std::nullopt;
  if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) throw std::runtime_error("the video node failed (unplugged?)");
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  if (Ioctl(fd_, VIDIOC_DQBUF, &b) != 0) {
    if (errno == EAGAIN) return std::nullopt;
    throw std::runtime_error(std::string("taking a frame: ") + std::strerror(errno));
  }
  lent_ = static_cast<int>(b.index);
  Buffer out;
  out.bytes = std::span<const std::uint8_t>(buffers_[b.index].data(), b.bytesused);
  out.stamp_ns =
      static_cast<TimeNs>(b.timestamp.tv_sec) * kNsPerSecond + static_cast<TimeNs>(b.timestamp.tv_usec) * 1000;
  out.sequence = b.sequence;
  return out;
}

}  // namespace corridor::drivers::realsense
