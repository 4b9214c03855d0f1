// corridor-stereo: a stereo camera's calibration from chessboard views, and a stereo matcher scored against a true
// disparity image (drivers/stereo). See --help.
#include <nlohmann/json.hpp>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "drivers/stereo/stereo_calibration.h"
#include "drivers/stereo/stereo_matcher.h"
#include "tools/common/command_line.h"

namespace {

using namespace corridor;
using drivers::stereo::Chessboard;
using drivers::stereo::DisparityScore;
using drivers::stereo::MatcherKind;
using drivers::stereo::ScoreDisparity;
using drivers::stereo::StereoCalibration;
using drivers::stereo::StereoCalibrationError;
using drivers::stereo::StereoMatcher;
using drivers::stereo::StereoMatcherOptions;
using drivers::stereo::ViewReport;
using nlohmann::json;

constexpr const char* kUsage = R"(usage: corridor-stereo calibrate IMAGE... --out FILE [options]
       corridor-stereo score LEFT RIGHT TRUTH [options]

calibrate: each camera's intrinsics and distortion and the pair's geometry from views of a printed chessboard, held
still at 0.5-2 m in a dozen or more places and angles, the whole board in both images. Pairs without the whole board
in both images are left out and listed. The file is what a stereo camera's `calibration` key names.

  IMAGE...           left and right images in turn (LEFT1 RIGHT1 LEFT2 RIGHT2 ...), or with --side-by-side each
                     image holds both views (the left camera's in its left half)
  --side-by-side     one image a pair, as a side-by-side UVC stereo camera gives them
  --board CxR        the board's inner corners, across and down (default 9x6)
  --square-m M       one square's side in metres (default 0.025)
  --out FILE         where the calibration goes (OpenCV YAML)
  --json             the result as JSON: {"views", "rms_px", "baseline_m", "left", "right", "pairs": [...]}
  --help

score: matches a rectified pair and counts, of the pixels with a true disparity, the share off by more than 1 px or
missing (as the Middlebury benchmark counts), and the share with a disparity at all. TRUTH is a grey PNG of the left
image's disparities (0 where unknown).

  --scale S          match the images and score against the truth resized by S (default 0.5: half size, as a
                     small robot matches)
  --truth-scale K    TRUTH's values are K times the full-size disparity in pixels (default 1; Middlebury's 2005 and
                     2006 full-size sets)
  --matcher NAME     sgbm (default) or bm: corridor's matcher as its depth path runs it; opencv-sgbm or opencv-bm:
                     OpenCV's matchers with their documented defaults (StereoSGBM::create(0, N, block),
                     StereoBM::create(N, block)), to compare
  --disparities N    the search range, a multiple of 16 (default 128);  --block PX: the block (default 5, bm 21)
  --min-texture G    (sgbm, bm) no disparity where the block varies less than G grey levels (default 3; 0: off)
  --bad-px PX        off by more than this is bad (default 1)
  --json             {"bad", "density", "scored", "ms", "size": [w, h], "matcher"}

Exit status: 0 done; 1 the views do not calibrate (too few boards found); 2 bad options or unreadable images.
)";

struct Options {
  std::vector<std::string> images;
  bool side_by_side = false;
  Chessboard board;
  std::string out;
  bool json = false;
};

cv::Size ParseBoard(const std::string& text) {
  const auto x = text.find('x');
  const auto whole = [&](const std::string& part) {
    int n = 0;
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), n);
    return error == std::errc() && end == part.data() + part.size() && n >= 2 && n <= 100 ? n : 0;
  };
  const int columns = x == std::string::npos ? 0 : whole(text.substr(0, x));
  const int rows = x == std::string::npos ? 0 : whole(text.substr(x + 1));
  if (columns == 0 || rows == 0) {
    throw std::invalid_argument("--board: expected inner corners as CxR from 2 to 100 (for example 9x6), got '" + text +
                                "'");
  }
  return {columns, rows};
}

Options ParseOptions(int argc, char** argv) {
  Options o;
  for (tools::Arguments args(argc, argv, 2); args.Next();) {
    const std::string arg = args.current();
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else if (arg == "--side-by-side") {
      o.side_by_side = true;
    } else if (arg == "--board") {
      o.board.inner_corners = ParseBoard(args.Value());
    } else if (arg == "--square-m") {
      o.board.square_m = tools::ParseNumber(arg, args.Value(), 0.001, 1.0);
    } else if (arg == "--out") {
      o.out = args.Value();
    } else if (arg == "--json") {
      o.json = true;
    } else if (arg.starts_with("--")) {
      throw std::invalid_argument("unknown option '" + arg + "'");
    } else {
      o.images.push_back(arg);
    }
  }
  if (o.out.empty()) throw std::invalid_argument("--out: where the calibration goes is required");
  if (o.images.empty()) throw std::invalid_argument("no images");
  if (!o.side_by_side && o.images.size() % 2 != 0) {
    throw std::invalid_argument(std::to_string(o.images.size()) +
                                " images: left and right in turn need an even number (or --side-by-side)");
  }
  return o;
}

cv::Mat ReadImage(const std::string& file) {
  cv::Mat image = cv::imread(file, cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw std::invalid_argument(file + ": not an image");
  return image;
}

json Camera(const drivers::stereo::CameraModel& c) {
  return {{"fx_px", c.matrix(0, 0)},
          {"fy_px", c.matrix(1, 1)},
          {"cx_px", c.matrix(0, 2)},
          {"cy_px", c.matrix(1, 2)},
          {"distortion", {c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3], c.distortion[4]}}};
}

int Calibrate(const Options& o) {
  std::vector<cv::Mat> left;
  std::vector<cv::Mat> right;
  std::vector<std::string> names;
  if (o.side_by_side) {
    for (const std::string& file : o.images) {
      const cv::Mat image = ReadImage(file);
      if (image.cols % 2 != 0) throw std::invalid_argument(file + ": an odd width cannot hold two views side by side");
      left.push_back(image.colRange(0, image.cols / 2).clone());
      right.push_back(image.colRange(image.cols / 2, image.cols).clone());
      names.push_back(file);
    }
  } else {
    for (std::size_t i = 0; i < o.images.size(); i += 2) {
      left.push_back(ReadImage(o.images[i]));
      right.push_back(ReadImage(o.images[i + 1]));
      names.push_back(o.images[i] + " " + o.images[i + 1]);
    }
  }
  std::vector<ViewReport> reports;
  StereoCalibration c;
  try {
    c = drivers::stereo::CalibrateStereo(left, right, o.board, &reports);
  } catch (const StereoCalibrationError& e) {
    for (std::size_t i = 0; i < reports.size(); ++i) {
      if (!reports[i].used) std::cerr << names[i] << ": " << reports[i].why_not << '\n';
    }
    std::cerr << "corridor-stereo: " << e.what() << '\n';
    return 1;
  }
  drivers::stereo::SaveStereoCalibration(o.out, c);
  if (o.json) {
    json pairs = json::array();
    for (std::size_t i = 0; i < reports.size(); ++i) {
      pairs.push_back({{"images", names[i]}, {"used", reports[i].used}, {"why_not", reports[i].why_not}});
    }
    std::cout << json{{"views", c.views},
                      {"rms_px", c.rms_px},
                      {"baseline_m", c.baseline_m()},
                      {"translation_m", {c.translation_m[0], c.translation_m[1], c.translation_m[2]}},
                      {"left", Camera(c.left)},
                      {"right", Camera(c.right)},
                      {"pairs", pairs},
                      {"out", o.out}}
                     .dump(2)
              << '\n';
    return 0;
  }
  for (std::size_t i = 0; i < reports.size(); ++i) {
    if (!reports[i].used) std::printf("left out: %s (%s)\n", names[i].c_str(), reports[i].why_not.c_str());
  }
  std::printf("%d pairs, reprojection error %.3f px (RMS), baseline %.4f m\n", c.views, c.rms_px, c.baseline_m());
  std::printf("left  fx %.2f fy %.2f cx %.2f cy %.2f px\nright fx %.2f fy %.2f cx %.2f cy %.2f px\n",
              c.left.matrix(0, 0), c.left.matrix(1, 1), c.left.matrix(0, 2), c.left.matrix(1, 2), c.right.matrix(0, 0),
              c.right.matrix(1, 1), c.right.matrix(0, 2), c.right.matrix(1, 2));
  std::printf("written to %s\n", o.out.c_str());
  return 0;
}

int Score(int argc, char** argv) {
  std::vector<std::string> files;
  double scale = 0.5;
  double truth_scale = 1.0;
  std::string matcher_name = "sgbm";
  StereoMatcherOptions options;
  options.disparities = 128;
  int block = 0;
  double bad_px = 1.0;
  bool as_json = false;
  for (tools::Arguments args(argc, argv, 2); args.Next();) {
    const std::string arg = args.current();
    if (arg == "--scale") {
      scale = tools::ParseNumber(arg, args.Value(), 0.05, 1.0);
    } else if (arg == "--truth-scale") {
      truth_scale = tools::ParseNumber(arg, args.Value(), 0.01, 100.0);
    } else if (arg == "--matcher") {
      matcher_name = args.Value();
      if (matcher_name != "sgbm" && matcher_name != "bm" && matcher_name != "opencv-sgbm" &&
          matcher_name != "opencv-bm") {
        throw std::invalid_argument("--matcher: sgbm, bm, opencv-sgbm or opencv-bm, got '" + matcher_name + "'");
      }
    } else if (arg == "--disparities") {
      options.disparities = static_cast<int>(tools::ParseNumber(arg, args.Value(), 16, 512));
    } else if (arg == "--block") {
      block = static_cast<int>(tools::ParseNumber(arg, args.Value(), 1, 51));
    } else if (arg == "--min-texture") {
      options.min_texture = tools::ParseNumber(arg, args.Value(), 0.0, 128.0);
    } else if (arg == "--bad-px") {
      bad_px = tools::ParseNumber(arg, args.Value(), 0.1, 100.0);
    } else if (arg == "--json") {
      as_json = true;
    } else if (arg.starts_with("--")) {
      throw std::invalid_argument("unknown option '" + arg + "'");
    } else {
      files.push_back(arg);
    }
  }
  if (files.size() != 3) throw std::invalid_argument("score needs LEFT RIGHT TRUTH");
  const bool block_matching = matcher_name.ends_with("bm") && !matcher_name.ends_with("sgbm");
  options.kind = block_matching ? MatcherKind::kBlock : MatcherKind::kSemiGlobal;
  options.block_px = block > 0 ? block : block_matching ? 21 : 5;
  ValidateMatcherOptions(options);
  const cv::Mat full_left = ReadImage(files[0]);
  const cv::Mat full_right = ReadImage(files[1]);
  const cv::Mat full_truth = ReadImage(files[2]);
  if (full_left.size() != full_right.size() || full_left.size() != full_truth.size()) {
    throw std::invalid_argument("LEFT, RIGHT and TRUTH must be of one size");
  }
  cv::Mat left;
  cv::Mat right;
  cv::Mat truth;
  cv::resize(full_left, left, {}, scale, scale, cv::INTER_AREA);
  cv::resize(full_right, right, {}, scale, scale, cv::INTER_AREA);
  cv::resize(full_truth, truth, left.size(), 0, 0, cv::INTER_NEAREST);  // disparities are not averaged
  truth.convertTo(truth, CV_32F, scale / truth_scale);

  // The time of one core, as on the robot's board where the other runs the rest.
  cv::setNumThreads(1);
  cv::Mat disparity;
  double ms = 0.0;
  if (matcher_name.starts_with("opencv-")) {
    cv::Ptr<cv::StereoMatcher> opencv =
        block_matching ? cv::Ptr<cv::StereoMatcher>(cv::StereoBM::create(options.disparities, options.block_px))
                       : cv::Ptr<cv::StereoMatcher>(cv::StereoSGBM::create(0, options.disparities, options.block_px));
    cv::Mat fixed_point;
    const auto start = std::chrono::steady_clock::now();
    opencv->compute(left, right, fixed_point);
    ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    fixed_point.convertTo(disparity, CV_32F, 1.0 / 16.0);
    disparity.setTo(std::numeric_limits<float>::quiet_NaN(), fixed_point < 0);
  } else {
    StereoMatcher matcher(options);
    matcher.Compute(left, right, disparity);  // the first run allocates the buffers
    const auto start = std::chrono::steady_clock::now();
    matcher.Compute(left, right, disparity);
    ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  const DisparityScore score = ScoreDisparity(disparity, truth, bad_px);
  if (as_json) {
    std::cout << json{{"matcher", matcher_name},
                      {"bad", score.bad},
                      {"density", score.density},
                      {"scored", score.scored},
                      {"ms", ms},
                      {"size", {left.cols, left.rows}},
                      {"disparities", options.disparities},
                      {"block_px", options.block_px}}
                     .dump(2)
              << '\n';
  } else {
    std::printf(
        "%s at %d x %d, %d disparities, block %d px: %.1f %% bad (off by more than %.1f px or missing), "
        "%.1f %% dense, %.1f ms on one core\n",
        matcher_name.c_str(), left.cols, left.rows, options.disparities, options.block_px, 100.0 * score.bad, bad_px,
        100.0 * score.density, ms);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "--help" || command == "-h") {
    std::cout << kUsage;
    return 0;
  }
  try {
    if (command == "calibrate") return Calibrate(ParseOptions(argc, argv));
    if (command == "score") return Score(argc, argv);
    throw std::invalid_argument("unknown command '" + command + "' (calibrate, score)");
  } catch (const std::invalid_argument& e) {
    std::cerr << "corridor-stereo: " << e.what() << "\n\n" << kUsage;
    return 2;
  } catch (const StereoCalibrationError& e) {
    std::cerr << "corridor-stereo: " << e.what() << '\n';
    return 2;
  }
}
