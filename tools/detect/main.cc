// corridor-detect: runs a detector of the detection hook (face/detect) on images or videos and prints what it finds;
// with --truth, scores people against hand-made boxes (precision and recall at IoU >= 0.5). See --help.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "face/detect/dnn_detector.h"
#include "face/detect/face_cascade.h"
#include "face/detect/hog_people.h"
#include "face/detect/people_detector.h"
#include "face/detect/tracker.h"
#include "tools/common/command_line.h"

namespace {

using namespace corridor;
using nlohmann::json;
using tools::ParseNumber;

constexpr const char* kUsage = R"(usage: corridor-detect IMAGE_OR_VIDEO... [options]

Runs one of corridor's detectors on each image, or each frame of each video, and prints the detections.

  --detector NAME    hog (default: OpenCV's HOG people detector), people (HOG with the head-and-shoulders and face
                     cascades: people near, sideways, sitting), face (the frontal face cascade), or dnn
  --upper-body-neighbours N, --face-neighbours N   (people) the cascades' neighbours (default 6 and 5)
  --no-upper-body, --no-faces                      (people) without that cascade
  --cascade-scale-step K                           (people) between the cascades' scales (default 1.1)
  --upscale K        (hog) enlarge the image K times first, for people under 128 px tall (default 1)
  --stride PX        (hog) the search's window stride (default 8)
  --scale-step K     (hog) between the search's scales (default 1.2)
  --padding PX       (hog) let windows reach this far past the image's edges (default 32)
  --hit-threshold M  (hog) the SVM margin a window needs (default 0);  --group N: windows to make one (default 2)
  --min-score S      (hog) drop detections scoring less (default 0.3)
  --cascade FILE     (face) the cascade (default: opencv-data's LBP frontal face)
  --model FILE       (dnn) an .onnx, or Darknet .weights with --config FILE.cfg
  --classes FILE     (dnn) the class names, one per line
  --input PX         (dnn) the network's input size (default 416)
  --transposed       (dnn) YOLOv8's output layout;  --pixels: boxes in input pixels (YOLOv5/v8 ONNX)
  --frames N         at most N frames of each video;  --every N: every N-th frame (default 1)
  --threads N        OpenCV's threads (default 1: the time of one core)
  --width PX         detect in each frame resized to this width (as a camera of that size would give it; the
                     time excludes the resizing); boxes are scaled back to the frame's pixels
  --truth FILE       score against hand-made boxes: [{"image": NAME, "frame": N, "people": [{"x","y","w","h"}]}]
                     (NAME the file's name; frames only those listed); people under --min-height px (default 96),
                     or marked "optional": true (mostly hidden), are neither required nor counted wrong
  --parts            a detection mostly inside a person's box (a face, an upper body) finds them too (MatchScore)
  --json             [{"image", "frame", "ms", "detections": [{"class", "score", "box": {"x", "y", "w", "h"}}]}]
                     (with --truth: {"frames": [...], "score": {...}})
  --save DIR         the frames with their boxes drawn (truth in green, detections in red)
  --help
)";

struct Options {
  std::vector<std::string> inputs;
  std::string detector = "hog";
  face::HogOptions hog;
  face::PeopleOptions people;
  face::FaceCascadeOptions cascade;
  face::DnnOptions dnn;
  long frames = -1;
  long every = 1;
  int threads = 1;
  int width = 0;  // resize each frame to this width first (0: as it is)
  std::string truth;
  double min_height_px = 96.0;
  bool parts = false;
  bool json = false;
  std::string save;
};

Options ParseOptions(int argc, char** argv) {
  Options o;
  for (tools::Arguments args(argc, argv, 1); args.Next();) {
    const std::string arg = args.current();
    const auto value = [&] { return args.Value(); };
    if (arg == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else if (arg == "--detector") {
      o.detector = value();
      if (o.detector != "hog" && o.detector != "face" && o.detector != "dnn" && o.detector != "people") {
        throw std::invalid_argument("--detector: hog, people, face or dnn, got '" + o.detector + "'");
      }
    } else if (arg == "--upscale") {
      o.hog.upscale = ParseNumber(arg, value(), 1, 4);
    } else if (arg == "--stride") {
      o.hog.window_stride_px = static_cast<int>(ParseNumber(arg, value(), 1, 64));
    } else if (arg == "--padding") {
      o.hog.padding_px = static_cast<int>(ParseNumber(arg, value(), 0, 64));
    } else if (arg == "--scale-step") {
      o.hog.scale_step = ParseNumber(arg, value(), 1.01, 2);
    } else if (arg == "--hit-threshold") {
      o.hog.hit_threshold = ParseNumber(arg, value(), -5, 5);
    } else if (arg == "--group") {
      o.hog.group_threshold = static_cast<int>(ParseNumber(arg, value(), 0, 20));
    } else if (arg == "--min-score") {
      o.hog.min_score = ParseNumber(arg, value(), 0, 1);
    } else if (arg == "--upper-body-neighbours") {
      o.people.upper_body_neighbours = static_cast<int>(ParseNumber(arg, value(), 0, 50));
    } else if (arg == "--face-neighbours") {
      o.people.face_neighbours = static_cast<int>(ParseNumber(arg, value(), 0, 50));
    } else if (arg == "--cascade-scale-step") {
      o.people.cascade_scale_step = ParseNumber(arg, value(), 1.01, 2.0);
    } else if (arg == "--no-upper-body") {
      o.people.upper_body = false;
    } else if (arg == "--no-faces") {
      o.people.faces = false;
    } else if (arg == "--cascade") {
      o.cascade.cascade = value();
    } else if (arg == "--model") {
      o.dnn.model = value();
    } else if (arg == "--config") {
      o.dnn.config = value();
    } else if (arg == "--classes") {
      o.dnn.classes = value();
    } else if (arg == "--input") {
      o.dnn.input_size_px = static_cast<int>(ParseNumber(arg, value(), 32, 2048));
    } else if (arg == "--transposed") {
      o.dnn.transposed = true;
    } else if (arg == "--pixels") {
      o.dnn.boxes_in_pixels = true;
    } else if (arg == "--frames") {
      o.frames = static_cast<long>(ParseNumber(arg, value(), 1, 1e9));
    } else if (arg == "--every") {
      o.every = static_cast<long>(ParseNumber(arg, value(), 1, 1e6));
    } else if (arg == "--width") {
      o.width = static_cast<int>(ParseNumber(arg, value(), 64, 4096));
    } else if (arg == "--threads") {
      o.threads = static_cast<int>(ParseNumber(arg, value(), 1, 64));
    } else if (arg == "--truth") {
      o.truth = value();
    } else if (arg == "--min-height") {
      o.min_height_px = ParseNumber(arg, value(), 0, 10000);
    } else if (arg == "--parts") {
      o.parts = true;
    } else if (arg == "--json") {
      o.json = true;
    } else if (arg == "--save") {
      o.save = value();
    } else if (!arg.empty() && arg[0] != '-') {
      o.inputs.push_back(arg);
    } else {
      throw std::invalid_argument("unknown option '" + arg + "' (see --help)");
    }
  }
  if (o.inputs.empty()) throw std::invalid_argument("no image or video given (see --help)");
  return o;
}

std::unique_ptr<face::Detector> MakeDetector(const Options& o) {
  if (o.detector == "face") return std::make_unique<face::FaceCascadeDetector>(o.cascade);
  if (o.detector == "dnn") return std::make_unique<face::DnnDetector>(o.dnn);
  if (o.detector == "people") {
    face::PeopleOptions people = o.people;
    people.hog = o.hog;
    return std::make_unique<face::PeopleDetector>(people);
  }
  return std::make_unique<face::HogPeopleDetector>(o.hog);
}

json BoxJson(const cv::Rect2d& b) { return {{"x", b.x}, {"y", b.y}, {"w", b.width}, {"h", b.height}}; }

cv::Rect2d BoxFrom(const json& j, const std::string& where) {
  for (const char* k : {"x", "y", "w", "h"}) {
    if (!j.contains(k) || !j[k].is_number()) throw std::invalid_argument(where + ": a box needs numbers x, y, w, h");
  }
  return {j["x"].get<double>(), j["y"].get<double>(), j["w"].get<double>(), j["h"].get<double>()};
}

// A hand-made box: a person's whole extent (hidden parts estimated); `optional` for one mostly hidden, whom a
// detector may find or miss at no cost.
struct TruthBox {
  cv::Rect2d box;
  bool optional = false;
};

// The hand-made boxes by (file name, frame).
std::map<std::pair<std::string, long>, std::vector<TruthBox>> ReadTruth(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot open");
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    throw std::invalid_argument(path + ": not JSON: " + e.what());
  }
  const json& frames = doc.is_object() && doc.contains("frames") ? doc["frames"] : doc;
  if (!frames.is_array()) throw std::invalid_argument(path + ": expected a list of frames");
  std::map<std::pair<std::string, long>, std::vector<TruthBox>> truth;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const json& f = frames[i];
    const std::string where = path + ": frame entry " + std::to_string(i);
    if (!f.is_object() || !f.contains("image") || !f["image"].is_string() || !f.contains("people") ||
        !f["people"].is_array()) {
      throw std::invalid_argument(where + ": needs \"image\" and \"people\"");
    }
    const long frame = f.contains("frame") && f["frame"].is_number_integer() ? f["frame"].get<long>() : 0;
    std::vector<TruthBox>& boxes = truth[{f["image"].get<std::string>(), frame}];
    for (const json& b : f["people"]) {
      boxes.push_back({BoxFrom(b, where), b.is_object() && b.value("optional", false)});
    }
  }
  return truth;
}

struct Score {
  long true_positives = 0;
  long false_positives = 0;
  long false_negatives = 0;
  long frames = 0;
};

// How well detection `d` finds the person in `t`: their IoU; with `parts`, also a part of them (a face, head and
// shoulders, an upper body, what shows beside what hides them) counts as finding them: at least 70 % of the detection
// inside the person's box and its height a sixth of theirs at least (then 0.5, a match).
double MatchScore(const cv::Rect2d& d, const cv::Rect2d& t, bool parts) {
  const double iou = face::IntersectionOverUnion(d, t);
  if (iou >= 0.5 || !parts) return iou;
  const double inside = (d & t).area() / std::max(d.area(), 1e-9);
  return inside >= 0.7 && d.height >= t.height / 6.0 ? 0.5 : iou;
}

// Greedy matching by score at IoU >= 0.5 (or parts: MatchScore). Truth under min_height, or marked optional, is
// optional: matching it counts nothing, missing it costs nothing; a detection under min_height matching nothing is not
// counted either.
void ScoreFrame(const std::vector<face::Detection>& detections, const std::vector<TruthBox>& truth, double min_height,
                bool parts, Score& score) {
  std::vector<const face::Detection*> people;
  for (const face::Detection& d : detections) {
    if (d.label == "person" && d.box) people.push_back(&d);
  }
  std::sort(people.begin(), people.end(), [](auto* a, auto* b) { return a->score > b->score; });
  const auto required = [&](const TruthBox& t) { return !t.optional && t.box.height >= min_height; };
  std::vector<bool> matched(truth.size(), false);
  for (const face::Detection* d : people) {
    int best = -1;
    double best_match = 0.5;
    for (std::size_t t = 0; t < truth.size(); ++t) {
      const double match = MatchScore(*d->box, truth[t].box, parts);
      if (!matched[t] && match >= best_match) {
        best_match = match;
        best = static_cast<int>(t);
      }
    }
    if (best >= 0) {
      matched[static_cast<std::size_t>(best)] = true;
      if (required(truth[static_cast<std::size_t>(best)])) ++score.true_positives;
    } else if (d->box->height >= min_height) {
      ++score.false_positives;
    }
  }
  for (std::size_t t = 0; t < truth.size(); ++t) {
    if (!matched[t] && required(truth[t])) ++score.false_negatives;
  }
  ++score.frames;
}

int Run(const Options& o) {
  cv::setNumThreads(o.threads);
  const std::unique_ptr<face::Detector> detector = MakeDetector(o);
  const auto truth = o.truth.empty() ? decltype(ReadTruth("")){} : ReadTruth(o.truth);
  if (!o.save.empty()) std::filesystem::create_directories(o.save);
  json frames = json::array();
  std::vector<double> times;
  Score score;
  for (const std::string& input : o.inputs) {
    const std::string name = std::filesystem::path(input).filename().string();
    cv::Mat image = cv::imread(input, cv::IMREAD_COLOR);
    cv::VideoCapture video;
    if (image.empty()) {
      video.open(input);
      if (!video.isOpened()) throw std::invalid_argument(input + ": neither an image nor a video OpenCV can read");
    }
    for (long frame = 0; o.frames < 0 || frame < o.frames * o.every; ++frame) {
      cv::Mat bgr;
      if (video.isOpened()) {
        if (!video.read(bgr)) break;
      } else {
        if (frame > 0) break;
        bgr = image;
      }
      if (frame % o.every != 0) continue;
      const auto key = std::make_pair(name, frame);
      if (!truth.empty() && !truth.contains(key)) continue;
      if (bgr.channels() == 1) cv::cvtColor(bgr, bgr, cv::COLOR_GRAY2BGR);
      cv::Mat input_frame = bgr;
      const double k = o.width > 0 ? static_cast<double>(bgr.cols) / o.width : 1.0;
      if (k != 1.0) {
        cv::resize(bgr, input_frame, {o.width, static_cast<int>(std::lround(bgr.rows / k))}, 0, 0, cv::INTER_AREA);
      }
      const auto start = std::chrono::steady_clock::now();
      std::vector<face::Detection> found = detector->Detect(input_frame, cv::Mat());
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      for (face::Detection& d : found) {
        if (d.box) *d.box = cv::Rect2d(d.box->x * k, d.box->y * k, d.box->width * k, d.box->height * k);
      }
      times.push_back(ms);
      json detections = json::array();
      for (const face::Detection& d : found) {
        detections.push_back(
            {{"class", d.label}, {"score", d.score}, {"box", d.box ? BoxJson(*d.box) : json(nullptr)}});
      }
      frames.push_back({{"image", name}, {"frame", frame}, {"ms", ms}, {"detections", detections}});
      if (!truth.empty()) ScoreFrame(found, truth.at(key), o.min_height_px, o.parts, score);
      if (!o.save.empty()) {
        cv::Mat drawn = bgr.clone();
        if (!truth.empty()) {
          for (const TruthBox& t : truth.at(key)) cv::rectangle(drawn, t.box, {0, 200, 0}, t.optional ? 1 : 2);
        }
        for (const face::Detection& d : found) {
          if (d.box) cv::rectangle(drawn, *d.box, {0, 0, 255}, 2);
        }
        char file[64];
        std::snprintf(file, sizeof file, "_%05ld.png", frame);
        cv::imwrite((std::filesystem::path(o.save) / (std::filesystem::path(name).stem().string() + file)).string(),
                    drawn);
      }
      if (!o.json) {
        std::printf("%s frame %ld: %zu detections (%.1f ms)\n", name.c_str(), frame, found.size(), ms);
        for (const face::Detection& d : found) {
          std::printf("  %s %.2f at (%.0f, %.0f) %.0f x %.0f\n", d.label.c_str(), d.score, d.box->x, d.box->y,
                      d.box->width, d.box->height);
        }
      }
    }
  }
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  double mean = 0.0;
  for (double t : times) mean += t / static_cast<double>(times.size());
  const double p99 = sorted.empty() ? 0.0 : sorted[std::min(sorted.size() - 1, sorted.size() * 99 / 100)];
  json result = frames;
  if (!truth.empty()) {
    const auto ratio = [](long a, long b) { return b > 0 ? json(static_cast<double>(a) / b) : json(nullptr); };
    const json s{{"frames", score.frames},
                 {"min_height_px", o.min_height_px},
                 {"true_positives", score.true_positives},
                 {"false_positives", score.false_positives},
                 {"false_negatives", score.false_negatives},
                 {"precision", ratio(score.true_positives, score.true_positives + score.false_positives)},
                 {"recall", ratio(score.true_positives, score.true_positives + score.false_negatives)},
                 {"ms_mean", mean},
                 {"ms_p99", p99},
                 {"threads", o.threads}};
    result = {{"frames", frames}, {"score", s}};
    if (!o.json) {
      std::printf(
          "%ld frames, people >= %.0f px: precision %s, recall %s (%ld found, %ld wrong, %ld missed); "
          "%.1f ms a frame (p99 %.1f) on %d thread(s)\n",
          score.frames, o.min_height_px, s["precision"].dump().c_str(), s["recall"].dump().c_str(),
          score.true_positives, score.false_positives, score.false_negatives, mean, p99, o.threads);
    }
  }
  if (o.json) std::cout << result.dump(2) << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(ParseOptions(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "corridor-detect: %s\n", e.what());
    return 2;
  }
}
