// A complete semfuse segmenter in one file, to copy as the start of your own: it labels every
// pixel nearer than 1.5 m as 1 ("near") and the rest as 2 ("far"), and publishes the result for
// every frame the server receives. Replace segmentDepth() with your model.
//
//   semfuse-example-segmenter [--domain-id N]      (Ctrl-C to stop)
#include <csignal>
#include <thread>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>

#include "semfuse/client/segmenter.hpp"
#include "semfuse/dds/participant.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;

semfuse::Result<semfuse::Segmentation> segmentDepth(const semfuse::Frame& frame) {
  semfuse::Segmentation result;
  const cv::Mat near = (frame.depth > 0.0F) & (frame.depth < 1.5F);
  result.labels = cv::Mat(frame.depth.size(), CV_16UC1, cv::Scalar(2));
  result.labels.setTo(1, near);
  result.labels.setTo(0, frame.depth <= 0.0F);  // no depth, no claim: 0 leaves the map as it is
  result.confidence = cv::Mat(frame.depth.size(), CV_32FC1, cv::Scalar(0.8F));
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Labels every pixel nearer than 1.5 m 1 and the rest 2, for every frame a semfuse server receives."};
  int domain = 0;
  semfuse::client::SegmenterOptions options;
  options.segmenter_id = "depth-threshold";
  app.add_option("--domain-id", domain, "DDS domain of the server")->capture_default_str();
  app.add_option("--segmenter-id", options.segmenter_id, "name in the server's status")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  std::signal(SIGINT, [](int) { g_stop = 1; });
  semfuse::dds::Participant participant(domain);
  semfuse::client::Segmenter segmenter(participant, segmentDepth, options);
  segmenter.start();
  while (!g_stop) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  segmenter.stop();
  const auto stats = segmenter.stats();
  spdlog::info("published {} segmentations, skipped {} frames, {:.1f} ms per frame", stats.published, stats.skipped,
               stats.meanSegmentMs());
  return 0;
}
