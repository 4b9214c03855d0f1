#include "face/detect/people_detector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "face/detect/tracker.h"

namespace corridor::face {
namespace {

void Load(cv::CascadeClassifier& cascade, const std::filesystem::path& file) {
  if (!cascade.load(file.string())) {
    throw std::invalid_argument("people: cannot read the cascade " + file.string() +
                                " (Debian's opencv-data has the cascades)");
  }
}

// `box` grown by the given fractions of its width and height on each side, clipped to `image`.
cv::Rect2d Grown(const cv::Rect& box, double left, double right, double up, double down, const cv::Size& image) {
  const cv::Rect2d grown(box.x - left * box.width, box.y - up * box.height, box.width * (1.0 + left + right),
                         box.height * (1.0 + up + down));
  return grown & cv::Rect2d(0.0, 0.0, image.width, image.height);
}

// The cascades search an image this wide at most (a larger one is shrunk first, the finds scaled back): at 640 px
// they took about a second a frame on one core; a person they find is 60 px or more in the full image, which they
// still see at half that.
constexpr int kCascadeWidthPx = 320;

}  // namespace

PeopleDetector::PeopleDetector(const PeopleOptions& options) : options_(options), hog_(options.hog) {
  if (!(options.cascade_scale_step > 1.0) || options.upper_body_neighbours < 0 || options.face_neighbours < 0 ||
      options.upper_body_min_px < 16 || options.face_min_px < 8 ||
      !(options.merge_iou > 0.0 && options.merge_iou < 1.0)) {
    throw std::invalid_argument(
        "people: cascade_scale_step > 1, neighbours >= 0, sizes of 16 and 8 px at least, "
        "merge_iou in (0, 1)");
  }
  if (options.upper_body) Load(upper_body_, options.upper_body_cascade);
  if (options.faces) {
    Load(frontal_, options.frontal_cascade);
    Load(profile_, options.profile_cascade);
  }
}

std::vector<cv::Rect> PeopleDetector::Find(cv::CascadeClassifier& cascade, const cv::Mat& gray, int neighbours,
                                           int min_px) const {
  const double scale = std::min(1.0, static_cast<double>(kCascadeWidthPx) / gray.cols);
  cv::Mat searched = gray;
  if (scale < 1.0) cv::resize(gray, searched, cv::Size(), scale, scale, cv::INTER_AREA);
  const int min_searched = std::max(20, static_cast<int>(std::lround(min_px * scale)));
  std::vector<cv::Rect> found;
  cascade.detectMultiScale(searched, found, options_.cascade_scale_step, neighbours, 0,
                           cv::Size(min_searched, min_searched));
  for (cv::Rect& r : found) {
    r = cv::Rect(static_cast<int>(std::lround(r.x / scale)), static_cast<int>(std::lround(r.y / scale)),
                 static_cast<int>(std::lround(r.width / scale)), static_cast<int>(std::lround(r.height / scale)));
  }
  return found;
}

std::vector<Detection> PeopleDetector::Detect(const cv::Mat& bgr, const cv::Mat& depth_mm) {
  if (bgr.type() != CV_8UC3) throw std::invalid_argument("people: the colour image must be CV_8UC3");
  std::vector<Detection> found = hog_.Detect(bgr, depth_mm);
  if (!options_.upper_body && !options_.faces) return found;
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  cv::equalizeHist(gray, gray);
  const cv::Size size = bgr.size();
  if (options_.upper_body) {
    // Head and shoulders: down to the waist, about as far again.
    for (const cv::Rect& r : Find(upper_body_, gray, options_.upper_body_neighbours, options_.upper_body_min_px)) {
      found.push_back(
          {"person", options_.upper_body_score, Grown(r, 0.0, 0.0, 0.0, 1.0, size), std::nullopt, 0, "upper_body"});
    }
  }
  if (options_.faces) {
    // A face: the head, the shoulders a face's width to either side, the chest three faces down.
    const auto add_face = [&](const cv::Rect& r, const char* source) {
      found.push_back({"person", options_.face_score, Grown(r, 1.0, 1.0, 0.25, 3.0, size), std::nullopt, 0, source});
    };
    for (const cv::Rect& r : Find(frontal_, gray, options_.face_neighbours, options_.face_min_px)) add_face(r, "face");
    for (const cv::Rect& r : Find(profile_, gray, options_.face_neighbours, options_.face_min_px)) {
      add_face(r, "profile_face");
    }
    // The profile cascade knows one side; the mirrored image shows it the other.
    cv::Mat mirrored;
    cv::flip(gray, mirrored, 1);
    for (cv::Rect r : Find(profile_, mirrored, options_.face_neighbours, options_.face_min_px)) {
      r.x = gray.cols - r.x - r.width;
      add_face(r, "profile_face");
    }
  }
  return MergePeople(std::move(found), options_.merge_iou);
}

std::vector<Detection> MergePeople(std::vector<Detection> found, double merge_iou) {
  std::vector<Detection> people;
  for (Detection& d : found) {
    if (!d.box) {
      people.push_back(std::move(d));
      continue;
    }
    bool merged = false;
    for (Detection& p : people) {
      if (!p.box || p.label != d.label) continue;
      const cv::Rect2d& a = *p.box;
      const cv::Rect2d& b = *d.box;
      const double smaller = std::min(a.area(), b.area());
      if (IntersectionOverUnion(a, b) <= merge_iou && (a & b).area() < 0.6 * smaller) continue;
      if (b.area() > a.area()) p.box = b;
      p.score = std::max(p.score, d.score);
      merged = true;
      break;
    }
    if (!merged) people.push_back(std::move(d));
  }
  return people;
}

}  // namespace corridor::face
