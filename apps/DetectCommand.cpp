// tkgslam detect IMAGE...: run the dynamic-object detector and draw the boxes into PNGs.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "Commands.h"
#include "DefaultFile.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/dynamic/YoloDetector.h"
#include "tkgslam/io/ColourImage.h"
#include "tkgslam/io/OutputFolder.h"

namespace tkgslam::app {

namespace {

struct DetectOptions {
  std::vector<std::string> images;
  std::string out = "detections";
  dynamic::DetectorParams params;
};

/// The images to process: files as given, folders replaced by their image files in name order.
std::vector<std::string> expandImages(const std::vector<std::string>& paths) {
  namespace fs = std::filesystem;
  std::vector<std::string> images;
  for (const auto& path : paths) {
    if (!fs::is_directory(path)) {
      images.push_back(path);
      continue;
    }
    std::vector<std::string> found;
    for (const auto& entry : fs::directory_iterator(path)) {
      std::string ext = entry.path().extension().string();
      for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
      const bool image = ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tif" ||
                         ext == ".tiff" || ext == ".webp";
      if (image && entry.is_regular_file()) found.push_back(entry.path().string());
    }
    if (found.empty()) throw InputError(fmt::format("folder '{}' has no images (png, jpg, bmp, tif, webp)", path));
    std::sort(found.begin(), found.end());
    images.insert(images.end(), found.begin(), found.end());
  }
  return images;
}

/// The drawing of `image` in `out_dir`.
std::filesystem::path drawingPath(const std::string& out_dir, const std::string& image) {
  return std::filesystem::path(out_dir) / (std::filesystem::path(image).stem().string() + "_det.png");
}

int runDetect(DetectOptions o) {
  const auto images = expandImages(o.images);
  std::map<std::filesystem::path, std::string> drawn;  // one drawing per image, none written over another
  for (const auto& path : images) {
    const auto [it, fresh] = drawn.emplace(drawingPath(o.out, path), path);
    if (!fresh) {
      throw InputError(fmt::format("'{}' and '{}' would both be drawn into '{}': give images with different names",
                                   it->second, path, it->first.string()));
    }
  }
  dynamic::YoloDetector detector(o.params);
  io::createOutputFolder(o.out);
  for (const auto& path : images) {
    const cv::Mat img = io::readColourImage(path);
    const auto t0 = std::chrono::steady_clock::now();
    const auto dets = detector.detect(img);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    cv::Mat vis = img.clone();
    const cv::Size input = detector.inputSize();
    const std::string extra =
        o.params.extra_input_size > 0 ? fmt::format(" and long side {}", o.params.extra_input_size) : "";
    std::printf("%s: %zu dynamic objects (%.1f ms at %d x %d%s)\n", path.c_str(), dets.size(), ms, input.width,
                input.height, extra.c_str());
    for (const auto& d : dets) {
      std::printf("  class %2d score %.3f box x %.1f y %.1f w %.1f h %.1f\n", d.class_id, d.score, d.box.x, d.box.y,
                  d.box.width, d.box.height);
      const cv::Scalar colour = d.class_id == 0 ? cv::Scalar(0, 0, 255) : cv::Scalar(255, 128, 0);
      cv::rectangle(vis, cv::Rect(d.box), colour, 2);
      cv::putText(vis, fmt::format("{} {:.2f}", d.class_id, d.score), d.box.tl() + cv::Point2f(2, 14),
                  cv::FONT_HERSHEY_SIMPLEX, 0.5, colour, 1);
    }
    const auto out = drawingPath(o.out, path);
    if (!cv::imwrite(out.string(), vis)) throw InputError(fmt::format("cannot write '{}'", out.string()));
  }
  std::printf("images with boxes in %s\n", o.out.c_str());
  return 0;
}

}  // namespace

Action addDetectCommand(CLI::App& app) {
  auto o = std::make_shared<DetectOptions>();
  o->params.model = "../shared/models/yolov5n-coco-640.onnx";
  auto* cmd = app.add_subcommand("detect", "Detect dynamic objects (YOLOv5) and draw them into PNGs");
  cmd->add_option("images", o->images, "Images to process (a folder: its images)")->required();
  cmd->add_option("-o,--out", o->out, "Output folder")->default_val(o->out);
  auto* model = cmd->add_option("--model", o->params.model, "YOLOv5 ONNX model")->default_val(o->params.model);
  cmd->add_option("--size", o->params.input_size, "Network input's long side (multiple of 32)")->default_val(640);
  cmd->add_option("--extra-size", o->params.extra_input_size,
                  "A second pass at this long side, boxes merged by NMS (e.g. 320: people too near for --size)")
      ->default_val(0);
  cmd->add_flag("!--square", o->params.fit_input,
                "Letterbox into a --size square instead of an input of the image's aspect ratio");
  cmd->add_option("--conf", o->params.confidence, "Score threshold")->default_val(0.25);
  cmd->add_option("--person-conf", o->params.person_confidence, "Score threshold for persons")->default_val(0.1);
  return [o, model] {
    requireDefaultFile(*model, "--model");
    return runDetect(*o);
  };
}

}  // namespace tkgslam::app
