#include "raycast_output.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "semfuse/wire/image_convert.hpp"

namespace semfuse::tools {
namespace {

// imwrite wants BGR; every colour image in semfuse is RGB.
bool writeRgb(const std::filesystem::path& file, const cv::Mat& rgb) {
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return cv::imwrite(file.string(), bgr);
}

}  // namespace

Result<std::vector<std::filesystem::path>> writeRaycastImages(const client::RaycastImages& images,
                                                              const LabelLegend& legend,
                                                              const std::filesystem::path& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) return makeError("cannot create " + folder.string() + ": " + ec.message());
  std::vector<std::filesystem::path> written;
  bool ok = true;
  const auto put = [&](const std::string& name, bool result) {
    ok = ok && result;
    written.push_back(folder / name);
  };
  if (!images.depth.empty()) {
    cv::Mat valid_depth;
    cv::patchNaNs(valid_depth = images.depth.clone(), 0.0);
    put("depth.png", writeRgb(folder / "depth.png", wire::colorizeDepth(valid_depth)));
    put("depth_mm.png", cv::imwrite((folder / "depth_mm.png").string(), wire::depthMetresToUnits(valid_depth)));
    put("depth.tiff", cv::imwrite((folder / "depth.tiff").string(), images.depth));
  }
  if (!images.normals.empty()) {
    cv::Mat normals;
    cv::patchNaNs(normals = images.normals.clone(), 0.0);
    cv::Mat shown;
    normals.convertTo(shown, CV_8UC3, 127.5, 127.5);  // [-1, 1] -> [0, 255] per axis
    put("normals.png", writeRgb(folder / "normals.png", shown));
    put("normals.tiff", cv::imwrite((folder / "normals.tiff").string(), images.normals));
  }
  if (!images.labels.empty()) {
    put("labels.png", writeRgb(folder / "labels.png", wire::colorizeLabels(images.labels, legend)));
    put("labels_raw.png", cv::imwrite((folder / "labels_raw.png").string(), images.labels));
  }
  if (!images.confidence.empty()) {
    cv::Mat confidence;
    cv::patchNaNs(confidence = images.confidence.clone(), 0.0);
    cv::Mat grey;
    confidence.convertTo(grey, CV_8UC1, 255.0);
    put("confidence.png", cv::imwrite((folder / "confidence.png").string(), grey));
    put("confidence.tiff", cv::imwrite((folder / "confidence.tiff").string(), images.confidence));
  }
  if (!images.color.empty()) put("color.png", writeRgb(folder / "color.png", images.color));
  if (!ok) return makeError("could not write every image to " + folder.string());
  return written;
}

}  // namespace semfuse::tools
