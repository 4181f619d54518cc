// semfuse-camera: replays RGB-D frames (7-Scenes, TUM RGB-D or the synthetic room) to the
// semfuse server on rt/semfuse/frames.
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "frame_source.hpp"
#include "semfuse/cli/command_line.hpp"
#include "semfuse/cli/exit_codes.hpp"
#include "semfuse/cli/progress.hpp"
#include "semfuse/cli/stop_signal.hpp"
#include "semfuse/client/camera_publisher.hpp"
#include "semfuse/core/logging.hpp"
#include "semfuse/dds/error.hpp"
#include "semfuse/dds/participant.hpp"

namespace {

using namespace semfuse;
using Clock = std::chrono::steady_clock;

struct Options {
  cli::CommonOptions common;
  std::string source;
  double rate_hz = 30.0;
  std::size_t first = 0;
  std::optional<std::size_t> last;
  std::size_t stride = 1;
  bool no_poses = false;
  std::string depth_encoding = "rvl";  // lossless, small, and the cheapest compressed depth to decode
  std::string color_encoding = "jpeg";
  int jpeg_quality = 90;
  std::string camera_id;
  bool loop = false;
  tools::SyntheticSourceOptions synthetic;
  double wait_server_s = 10.0;
  double ack_timeout_s = 10.0;
};

void addOptions(CLI::App& app, Options& o) {
  // The form is checked here so that a typo is a usage error (exit 2); a folder that is not a
  // dataset is found out when it is opened.
  const CLI::Validator source_form(
      [](std::string& spec) -> std::string {
        if (spec == "synthetic") return {};
        for (const char* kind : {"7scenes:", "tum:"}) {
          if (spec.rfind(kind, 0) == 0 && spec.size() > std::string(kind).size()) return {};
        }
        return "must be 7scenes:DIR, tum:DIR or synthetic";
      },
      "SOURCE");
  app.add_option("--source", o.source, "7scenes:DIR, tum:DIR or synthetic")->required()->check(source_form);
  app.add_option("--rate", o.rate_hz, "frames per second; 0 = as fast as the server acknowledges")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--first", o.first, "index of the first frame")->capture_default_str();
  app.add_option("--last", o.last, "index of the last frame (default: the last one)");
  app.add_option("--stride", o.stride, "send every Nth frame")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_flag("--no-poses", o.no_poses, "send frames without their poses (the server tracks them)");
  app.add_option("--depth-encoding", o.depth_encoding, "raw (16-bit mm), float (32-bit m), png or rvl (16-bit mm)")
      ->check(CLI::IsMember({"raw", "float", "png", "rvl"}))
      ->capture_default_str();
  app.add_option("--color-encoding", o.color_encoding, "none, raw, jpeg or png")
      ->check(CLI::IsMember({"none", "raw", "jpeg", "png"}))
      ->capture_default_str();
  app.add_option("--jpeg-quality", o.jpeg_quality, "JPEG quality")->check(CLI::Range(1, 100))->capture_default_str();
  app.add_option("--camera-id", o.camera_id, "camera id on the wire (default: the source's: 7scenes, tum, synthetic)");
  app.add_flag("--loop", o.loop, "start over after the last frame until interrupted");
  app.add_option("--frames", o.synthetic.frames, "synthetic: frames in the orbit")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--seed", o.synthetic.seed, "synthetic: texture and depth-noise seed")->capture_default_str();
  app.add_flag("--depth-noise", o.synthetic.depth_noise, "synthetic: Kinect-like depth noise");
  app.add_option("--wait-server", o.wait_server_s,
                 "seconds to wait for a server before the first frame (0 = do not wait; early frames may be lost)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--ack-timeout", o.ack_timeout_s, "seconds to wait at the end until the server has every frame")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cli::addCommonOptions(app, o.common);
}

std::chrono::milliseconds millis(double seconds) {
  return std::chrono::milliseconds(static_cast<long>(seconds * 1000.0));
}

// Frame indices to send in one pass: first, first + stride, ... up to last.
std::size_t framesPerPass(std::size_t first, std::size_t last, std::size_t stride) {
  return first > last ? 0 : (last - first) / stride + 1;
}

int run(const Options& o) {
  auto opened = tools::openFrameSource(o.source, o.synthetic);
  if (!opened) {
    spdlog::error("{}", opened.error());
    return cli::kExitFailure;
  }
  const tools::FrameSource& source = *opened.value();
  if (source.count() == 0 || o.first >= source.count()) {
    spdlog::error("{} has {} frames; --first {} is past the end", source.describe(), source.count(), o.first);
    return cli::kExitUsage;
  }
  const std::size_t last = std::min(o.last.value_or(source.count() - 1), source.count() - 1);
  const std::size_t per_pass = framesPerPass(o.first, last, o.stride);
  if (per_pass == 0) {
    spdlog::error("--first {} is after --last {}", o.first, last);
    return cli::kExitUsage;
  }

  dds::Participant participant(o.common.domain_id < 0 ? DDS_DOMAIN_DEFAULT
                                                      : static_cast<dds_domainid_t>(o.common.domain_id));
  client::CameraPublisherOptions publisher_options;
  publisher_options.depth_encoding = *client::parseDepthEncoding(o.depth_encoding);
  publisher_options.color_encoding = *client::parseColorEncoding(o.color_encoding);
  publisher_options.jpeg_quality = o.jpeg_quality;
  client::CameraPublisher camera(participant, publisher_options);

  spdlog::info("replaying {}: frames {}..{} stride {} ({} per pass){} at {}", source.describe(), o.first, last,
               o.stride, per_pass, o.loop ? ", looping" : "",
               o.rate_hz > 0 ? fmt::format("{} Hz", o.rate_hz) : std::string("full speed"));
  // A reliable writer keeps nothing for readers it has not discovered yet: frames written before
  // the server's reader is matched would simply be lost.
  if (o.wait_server_s > 0 && !camera.waitForServer(millis(o.wait_server_s))) {
    spdlog::error(
        "no semfuse server is reading rt/semfuse/frames after {} s (is semfuse-server running on "
        "this domain?)",
        o.wait_server_s);
    return cli::kExitTimeout;
  }

  cli::Progress progress("semfuse-camera", o.loop ? 0 : per_pass);
  const auto start = Clock::now();
  std::size_t sent = 0;
  std::size_t failed = 0;
  for (std::size_t pass = 0; !cli::stopRequested(); ++pass) {
    for (std::size_t k = 0; k < per_pass && !cli::stopRequested(); ++k) {
      const std::size_t index = o.first + k * o.stride;
      auto frame = source.load(index);
      if (!frame) {
        spdlog::warn("skipping frame {}: {}", index, frame.error());
        ++failed;
        continue;
      }
      Frame& f = frame.value();
      if (!o.camera_id.empty()) f.camera_id = o.camera_id;
      if (o.no_poses) f.camera_to_world.reset();
      // Sequence numbers keep growing across passes: the server matches segmentations to frames by them.
      f.seq += pass * (last + 1);
      if (o.rate_hz > 0) {
        std::this_thread::sleep_until(
            start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(sent / o.rate_hz)));
      }
      if (Status s = camera.publish(f); !s) {
        spdlog::warn("frame {} not sent: {}", f.seq, s.error());
        ++failed;
        continue;
      }
      ++sent;
      progress.update(o.loop ? sent : k + 1);
    }
    if (!o.loop) break;
  }
  progress.finish();
  if (cli::stopRequested()) spdlog::info("interrupted after {} frames", sent);

  // Exiting deletes the writer, and with it whatever the server has not acknowledged yet.
  if (Status acked = camera.waitForAcknowledgements(millis(o.ack_timeout_s)); !acked) {
    spdlog::error("the server did not acknowledge every frame: {}", acked.error());
    return cli::kExitTimeout;
  }
  spdlog::info("sent {} frames ({} failed), all acknowledged", sent, failed);
  return failed == 0 ? cli::kExitOk : cli::kExitFailure;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Replays RGB-D frames (7-Scenes, TUM RGB-D or the built-in synthetic room) to a semfuse server.",
               "semfuse-camera"};
  Options options;
  addOptions(app, options);
  if (const int code = cli::parseCommandLine(app, argc, argv); code >= 0) return code;
  if (Status s = setupLogging("semfuse-camera", options.common.log_level); !s) {
    spdlog::error("{}", s.error());
    return cli::kExitUsage;
  }
  cli::installStopHandler();
  try {
    return run(options);
  } catch (const dds::DdsError& e) {
    spdlog::error("DDS: {}", e.what());
    return cli::kExitFailure;
  }
}
