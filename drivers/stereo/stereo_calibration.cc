#include "drivers/stereo/stereo_calibration.h"

#include <algorithm>
#include <system_error>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace corridor::drivers::stereo {
namespace {

std::vector<cv::Point3f> BoardPoints(const Chessboard& board) {
  std::vector<cv::Point3f> points;
  for (int row = 0; row < board.inner_corners.height; ++row) {
    for (int col = 0; col < board.inner_corners.width; ++col) {
      points.emplace_back(static_cast<float>(col * board.square_m), static_cast<float>(row * board.square_m), 0.0f);
    }
  }
  return points;
}

cv::Mat Grey(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  return grey;
}

// One camera alone: its intrinsics from its views, the start of the pair's joint refinement.
CameraModel CalibrateCamera(const std::vector<std::vector<cv::Point3f>>& object,
                            const std::vector<std::vector<cv::Point2f>>& image, cv::Size size) {
  cv::Mat matrix;
  cv::Mat distortion;
  std::vector<cv::Mat> rotations;
  std::vector<cv::Mat> translations;
  cv::calibrateCamera(object, image, size, matrix, distortion, rotations, translations);
  CameraModel model;
  model.matrix = cv::Matx33d(matrix);
  for (int i = 0; i < 5; ++i) model.distortion[i] = distortion.at<double>(i);
  return model;
}

}  // namespace

std::vector<cv::Point2f> FindChessboard(const cv::Mat& image, const Chessboard& board) {
  std::vector<cv::Point2f> corners;
  if (image.empty()) return corners;
  // The sector-based detector: corners to a fraction of a pixel without a refinement step, and robust to blur and
  // to uneven light, which cheap cameras give. The exhaustive search takes three times as long: only when the quick
  // one fails. (Its "accuracy" mode lost one of opencv-doc's 26 views and gained nothing measurable.)
  const cv::Mat grey = Grey(image);
  if (cv::findChessboardCornersSB(grey, board.inner_corners, corners, cv::CALIB_CB_NORMALIZE_IMAGE)) return corners;
  if (cv::findChessboardCornersSB(grey, board.inner_corners, corners,
                                  cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_EXHAUSTIVE)) {
    return corners;
  }
  corners.clear();
  return corners;
}

StereoCalibration CalibrateStereo(const std::vector<cv::Mat>& left, const std::vector<cv::Mat>& right,
                                  const Chessboard& board, std::vector<ViewReport>* reports, int min_views) {
  if (left.size() != right.size()) {
    throw StereoCalibrationError("calibration needs pairs: " + std::to_string(left.size()) + " left images and " +
                                 std::to_string(right.size()) + " right");
  }
  if (board.inner_corners.width < 2 || board.inner_corners.height < 2 || !(board.square_m > 0.0)) {
    throw StereoCalibrationError("the chessboard needs at least 2 x 2 inner corners and squares of some size");
  }
  StereoCalibration result;
  if (reports != nullptr) reports->assign(left.size(), ViewReport{});
  const std::vector<cv::Point3f> board_points = BoardPoints(board);
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> left_corners;
  std::vector<std::vector<cv::Point2f>> right_corners;
  for (std::size_t i = 0; i < left.size(); ++i) {
    for (const cv::Mat* image : {&left[i], &right[i]}) {
      if (image->empty()) throw StereoCalibrationError("pair " + std::to_string(i + 1) + ": an empty image");
      if (result.image_size.empty()) result.image_size = image->size();
      if (image->size() != result.image_size) {
        throw StereoCalibrationError("pair " + std::to_string(i + 1) + ": an image of " + std::to_string(image->cols) +
                                     " x " + std::to_string(image->rows) + " px among images of " +
                                     std::to_string(result.image_size.width) + " x " +
                                     std::to_string(result.image_size.height));
      }
    }
    std::vector<cv::Point2f> l = FindChessboard(left[i], board);
    std::vector<cv::Point2f> r = FindChessboard(right[i], board);
    if (l.empty() || r.empty()) {
      if (reports != nullptr) {
        (*reports)[i].why_not = l.empty() && r.empty() ? "no whole board in either image"
                                : l.empty()            ? "no whole board in the left image"
                                                       : "no whole board in the right image";
      }
      continue;
    }
    // A board with an odd and an even number of corners is found from either end: side by side cameras see it the
    // same way up, so the two corner lists must run the same way.
    if ((l.back() - l.front()).dot(r.back() - r.front()) < 0.0f) std::reverse(r.begin(), r.end());
    object.push_back(board_points);
    left_corners.push_back(std::move(l));
    right_corners.push_back(std::move(r));
    if (reports != nullptr) (*reports)[i].used = true;
  }
  result.views = static_cast<int>(object.size());
  if (result.views < min_views) {
    throw StereoCalibrationError("the whole board is in both images of " + std::to_string(result.views) +
                                 " pairs: calibration needs at least " + std::to_string(min_views));
  }
  result.left = CalibrateCamera(object, left_corners, result.image_size);
  result.right = CalibrateCamera(object, right_corners, result.image_size);
  cv::Mat left_matrix(result.left.matrix);
  cv::Mat right_matrix(result.right.matrix);
  cv::Mat left_distortion(result.left.distortion);
  cv::Mat right_distortion(result.right.distortion);
  cv::Mat rotation;
  cv::Mat translation;
  cv::Mat essential;
  cv::Mat fundamental;
  result.rms_px = cv::stereoCalibrate(object, left_corners, right_corners, left_matrix, left_distortion, right_matrix,
                                      right_distortion, result.image_size, rotation, translation, essential,
                                      fundamental, cv::CALIB_USE_INTRINSIC_GUESS,
                                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-6));
  result.left.matrix = cv::Matx33d(left_matrix);
  result.right.matrix = cv::Matx33d(right_matrix);
  for (int i = 0; i < 5; ++i) {
    result.left.distortion[i] = left_distortion.at<double>(i);
    result.right.distortion[i] = right_distortion.at<double>(i);
  }
  result.rotation = cv::Matx33d(rotation);
  result.translation_m = cv::Vec3d(translation);
  return result;
}

void SaveStereoCalibration(const std::filesystem::path& file, const StereoCalibration& c) {
  const std::filesystem::path temporary = file.string() + ".tmp";
  try {
    cv::FileStorage out(temporary.string(), cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
    if (!out.isOpened()) throw StereoCalibrationError(file.string() + ": cannot be written");
    out << "image_width" << c.image_size.width << "image_height" << c.image_size.height;
    out << "left_camera_matrix" << cv::Mat(c.left.matrix) << "left_distortion" << cv::Mat(c.left.distortion);
    out << "right_camera_matrix" << cv::Mat(c.right.matrix) << "right_distortion" << cv::Mat(c.right.distortion);
    out << "rotation" << cv::Mat(c.rotation) << "translation_m" << cv::Mat(c.translation_m);
    out << "baseline_m" << c.baseline_m() << "rms_px" << c.rms_px << "views" << c.views;
    out.release();
  } catch (const cv::Exception& e) {
    throw StereoCalibrationError(file.string() + ": cannot be written (" + e.what() + ")");
  }
  std::error_code error;
  std::filesystem::rename(temporary, file, error);
  if (error) throw StereoCalibrationError(file.string() + ": cannot be written (" + error.message() + ")");
}

namespace {

// The matrix stored under `key` with `rows` x `cols` numbers; StereoCalibrationError naming the key otherwise.
cv::Mat ReadMatrix(const cv::FileStorage& in, const std::string& file, const char* key, int rows, int cols) {
  cv::Mat m;
  const cv::FileNode node = in[key];
  if (!node.empty()) node >> m;
  if (m.empty() || static_cast<int>(m.total()) != rows * cols || m.channels() != 1) {
    throw StereoCalibrationError(file + ": " + key + " must be a " + std::to_string(rows) + " x " +
                                 std::to_string(cols) + " matrix");
  }
  m.convertTo(m, CV_64F);
  m = m.reshape(1, rows);
  if (!cv::checkRange(m)) throw StereoCalibrationError(file + ": " + key + " holds a number that is not finite");
  return m;
}

int ReadSize(const cv::FileStorage& in, const std::string& file, const char* key) {
  const cv::FileNode node = in[key];
  if (!node.isInt() || static_cast<int>(node) < 1 || static_cast<int>(node) > 100000) {
    throw StereoCalibrationError(file + ": " + key + " must be a whole number of pixels");
  }
  return static_cast<int>(node);
}

}  // namespace

StereoCalibration LoadStereoCalibration(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) throw StereoCalibrationError(name + ": no such file");
  StereoCalibration c;
  try {
    cv::FileStorage in(name, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
    if (!in.isOpened()) throw StereoCalibrationError(name + ": cannot be read");
    c.image_size = cv::Size(ReadSize(in, name, "image_width"), ReadSize(in, name, "image_height"));
    c.left.matrix = cv::Matx33d(ReadMatrix(in, name, "left_camera_matrix", 3, 3));
    c.left.distortion = cv::Vec<double, 5>(ReadMatrix(in, name, "left_distortion", 5, 1));
    c.right.matrix = cv::Matx33d(ReadMatrix(in, name, "right_camera_matrix", 3, 3));
    c.right.distortion = cv::Vec<double, 5>(ReadMatrix(in, name, "right_distortion", 5, 1));
    c.rotation = cv::Matx33d(ReadMatrix(in, name, "rotation", 3, 3));
    c.translation_m = cv::Vec3d(ReadMatrix(in, name, "translation_m", 3, 1));
    if (in["rms_px"].isReal()) c.rms_px = static_cast<double>(in["rms_px"]);
    if (in["views"].isInt()) c.views = static_cast<int>(in["views"]);
  } catch (const cv::Exception& e) {
    throw StereoCalibrationError(name + ": not a calibration file (" + e.what() + ")");
  }
  for (const CameraModel* camera : {&c.left, &c.right}) {
    if (!(camera->matrix(0, 0) > 0.0 && camera->matrix(1, 1) > 0.0)) {
      throw StereoCalibrationError(name + ": a camera matrix with a focal length that is not positive");
    }
  }
  if (std::abs(cv::determinant(c.rotation) - 1.0) > 1e-3) {
    throw StereoCalibrationError(name + ": rotation is not a rotation matrix");
  }
  if (!(c.baseline_m() > 0.0)) throw StereoCalibrationError(name + ": translation_m puts both cameras at one place");
  return c;
}

StereoRectification Rectify(const StereoCalibration& c, double alpha) {
  cv::Mat r1;
  cv::Mat r2;
  cv::Mat p1;
  cv::Mat p2;
  cv::Mat q;
  cv::Rect left_valid;
  cv::Rect right_valid;
  cv::stereoRectify(c.left.matrix, c.left.distortion, c.right.matrix, c.right.distortion, c.image_size, c.rotation,
                    c.translation_m, r1, r2, p1, p2, q, cv::CALIB_ZERO_DISPARITY, alpha, c.image_size, &left_valid,
                    &right_valid);
  StereoRectification out;
  cv::initUndistortRectifyMap(c.left.matrix, c.left.distortion, r1, p1, c.image_size, CV_32FC1, out.left_map_x,
                              out.left_map_y);
  cv::initUndistortRectifyMap(c.right.matrix, c.right.distortion, r2, p2, c.image_size, CV_32FC1, out.right_map_x,
                              out.right_map_y);
  out.focal_px = p1.at<double>(0, 0);
  out.principal_px = cv::Point2d(p1.at<double>(0, 2), p1.at<double>(1, 2));
  // P2's fourth column is the right camera's offset times the focal length: -f * baseline for a horizontal pair.
  out.baseline_m = std::abs(p2.at<double>(0, 3)) / out.focal_px;
  out.left_rotation = cv::Matx33d(r1);
  out.valid = left_valid & right_valid;
  return out;
}

}  // namespace corridor::drivers::stereo
