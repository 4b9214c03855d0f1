// corridor-stereo: a stereo camera's calibration from chessboard views (drivers/stereo). See --help.
#include <nlohmann/json.hpp>

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "drivers/stereo/stereo_calibration.h"
#include "tools/common/command_line.h"

namespace {

using namespace corridor;
using drivers::stereo::Chessboard;
using drivers::stereo::StereoCalibration;
using drivers::stereo::StereoCalibrationError;
using drivers::stereo::ViewReport;
using nlohmann::json;

constexpr const char* kUsage = R"(usage: corridor-stereo calibrate IMAGE... --out FILE [options]

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

Exit status: 0 calibrated, 1 the views do not calibrate (too few boards found), 2 bad options or unreadable images.
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

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "--help" || command == "-h") {
    std::cout << kUsage;
    return 0;
  }
  try {
    if (command != "calibrate") throw std::invalid_argument("unknown command '" + command + "' (calibrate)");
    return Calibrate(ParseOptions(argc, argv));
  } catch (const std::invalid_argument& e) {
    std::cerr << "corridor-stereo: " << e.what() << "\n\n" << kUsage;
    return 2;
  } catch (const StereoCalibrationError& e) {
    std::cerr << "corridor-stereo: " << e.what() << '\n';
    return 2;
  }
}
