#pragma once
// Shared by the interop tests: a domain of their own, the synthetic room written as a frame
// folder for foreign peers, running a command with its output captured, and checking the
// server's map against the scene with a raycast.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <opencv2/core.hpp>

#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "test_domain.hpp"

namespace semfuse::testing {

// A domain of this test process's own (test_domain.hpp).
inline int interopDomain() { return reserveTestDomain(); }

// Runs `command` through the shell with stdout and stderr into files; returns the exit code.
inline int runCommand(const std::string& command, const std::filesystem::path& out, const std::filesystem::path& err) {
  const std::string line = command + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(line.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string tail(const std::string& text, size_t chars = 3000) {
  return text.size() <= chars ? text : "..." + text.substr(text.size() - chars);
}

// The folder fastdds_peer publishes: camera.txt, NNNN.depth (uint16 mm), NNNN.rgb, NNNN.pose.
inline void writeFrameFolder(const synthetic::SyntheticSequence& sequence, int frames,
                             const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const PinholeIntrinsics& k = sequence.config().intrinsics;
  std::ofstream(dir / "camera.txt") << k.width << " " << k.height << " " << k.fx << " " << k.fy << " " << k.cx << " "
                                    << k.cy << "\n";
  for (int i = 0; i < frames; ++i) {
    auto frame = sequence.frame(i);
    if (!frame.ok()) throw std::runtime_error(frame.error());
    char stem[16];
    std::snprintf(stem, sizeof stem, "%04d", i);
    cv::Mat millimetres;
    frame.value().depth.convertTo(millimetres, CV_16UC1, 1000.0);
    std::ofstream(dir / (std::string(stem) + ".depth"), std::ios::binary)
        .write(reinterpret_cast<const char*>(millimetres.data), static_cast<std::streamsize>(millimetres.total() * 2));
    const cv::Mat& rgb = frame.value().color;
    std::ofstream(dir / (std::string(stem) + ".rgb"), std::ios::binary)
        .write(reinterpret_cast<const char*>(rgb.data), static_cast<std::streamsize>(rgb.total() * 3));
    std::ofstream pose(dir / (std::string(stem) + ".pose"));
    pose.precision(17);
    const Eigen::Matrix4d m = frame.value().camera_to_world->matrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) pose << m(r, c) << (c == 3 ? "\n" : " ");
  }
}

}  // namespace semfuse::testing
