// semfuse-viewer end to end: a real server, the synthetic camera, the ground-truth segmenter and
// the viewer over loopback DDS; headless Chromium opens the page (page_snapshot.mjs) and the test
// checks what it shows: the table's and the floor's legend colours where the room's table top
// and floor must appear on screen, every large label of the room in the picture and in the
// legend, the frame counter advancing to the last frame, one camera path point per integrated
// frame, and a click on the table top answered as table (labels_at) with a raycast image from the
// view in which the table and the floor appear. The screenshot stays as
// tests/viewer/viewer_page.png in the build tree.
#include <sys/socket.h>

#include <netinet/in.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "eventually.hpp"
#include "semfuse/core/legend.hpp"
#include "server_harness.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;

namespace {

constexpr int kFrames = 60;  // the whole orbit, seen in 60 views

// A port nobody listens on now (the viewer binds it right after).
int freePort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof(address);
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), size);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
  ::close(fd);
  return ntohs(address.sin_port);
}

// Waits for the child's exit; its exit code, or -1 after SIGKILL at the timeout.
int waitExit(ChildProcess& child, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (child.running() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(100ms);
  return child.stop(9 /* SIGKILL */, 1000);
}

struct PageFacts {
  std::map<std::string, double> values;              // blocks, poses, frames
  std::vector<int> frames_seen;                      // counter values in the order the page showed them
  std::vector<std::string> legend;                   // "name count" rows
  std::map<std::string, cv::Point> points;           // name -> pixel
  std::vector<std::string> probe;                    // the page's answer to a click on the first point
  cv::Size raycast_size;                             // the raycast from the clicked view
  std::map<std::array<int, 3>, int> raycast_colors;  // its pixels by RGB
};

PageFacts readFacts(const std::string& path) {
  PageFacts facts;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string key;
    row >> key;
    if (key == "frames_seen") {
      for (int n; row >> n;) facts.frames_seen.push_back(n);
    } else if (key == "legend") {
      std::string rest;
      std::getline(row >> std::ws, rest);
      facts.legend.push_back(rest);
    } else if (key == "raycast_size") {
      row >> facts.raycast_size.width >> facts.raycast_size.height;
    } else if (key == "raycast_color") {
      std::array<int, 3> rgb{};
      int n = 0;
      row >> rgb[0] >> rgb[1] >> rgb[2] >> n;
      facts.raycast_colors[rgb] = n;
    } else if (key == "probe") {
      std::string rest;
      std::getline(row >> std::ws, rest);
      facts.probe.push_back(rest);
    } else if (key == "point") {
      std::string name;
      double x = 0, y = 0;
      row >> name >> x >> y;
      facts.points[name] = {static_cast<int>(x), static_cast<int>(y)};
    } else {
      row >> facts.values[key];
    }
  }
  return facts;
}

cv::Vec3b bgr(const LabelLegend& legend, LabelId id) {
  const auto rgb = legend.colorOf(id);
  return {rgb[2], rgb[1], rgb[0]};
}

int countColor(const cv::Mat& image, const cv::Vec3b& color) {
  int n = 0;
  image.forEach<cv::Vec3b>([&](const cv::Vec3b& p, const int*) {
    if (p == color) __atomic_add_fetch(&n, 1, __ATOMIC_RELAXED);
  });
  return n;
}

// Share of the pixels within 4 of `at` that have exactly `color`.
double shareAround(const cv::Mat& image, cv::Point at, const cv::Vec3b& color) {
  int hits = 0, all = 0;
  for (int dy = -4; dy <= 4; ++dy)
    for (int dx = -4; dx <= 4; ++dx) {
      const cv::Point p = at + cv::Point(dx, dy);
      if (p.x < 0 || p.y < 0 || p.x >= image.cols || p.y >= image.rows) continue;
      ++all;
      hits += image.at<cv::Vec3b>(p) == color ? 1 : 0;
    }
  return all ? static_cast<double>(hits) / all : 0.0;
}

}  // namespace

TEST(ViewerPage, ShowsTheRoomGrowWithItsLabelsLegendAndCounters) {
  const dds_domainid_t domain = serverTestDomain();
  ServerHarness h(domain);
  // The whole run fits in the camera's queue: on a loaded machine (ctest runs other servers beside
  // this one) fusion falls behind a 20 Hz camera, and the default queue of 4 would drop frames
  // (counted) that the page is then waited for in vain. The page is under test here, not pacing.
  h.startServer({"--legend", "synthetic", "--voxel-size", "0.03", "--truncation", "0.12", "--map-updates.rate", "4",
                 "--queue-per-camera", std::to_string(kFrames), "--max-queue-wait", "0"});
  const std::vector<std::string> dds{"--domain-id",     std::to_string(domain), "--dds-profile",
                                     loopbackProfile(), "--log-level",          "warn"};
  auto with = [&](std::vector<std::string> args) {
    args.insert(args.begin() + 1, dds.begin(), dds.end());
    return args;
  };

  const int port = freePort();
  ChildProcess viewer(with({SEMFUSE_VIEWER_EXE, "--port", std::to_string(port), "--legend", "synthetic"}));
  ChildProcess segmenter(with({SEMFUSE_SEGMENTER_EXE, "--backend", "gt"}));

  const std::string dir = std::string(SEMFUSE_BINARY_DIR) + "/tests/viewer";
  const std::string png = dir + "/viewer_page.png", facts_file = dir + "/viewer_page_facts.txt",
                    ready_file = dir + "/viewer_page_ready.txt";
  for (const std::string& file : {png, facts_file, ready_file}) std::remove(file.c_str());
  // Points of the room (common/synthetic/room.cpp) in plain view from above: the table top
  // beside the small sphere, and open floor between the table and the near wall.
  ChildProcess browser({SEMFUSE_NODE_EXE, "--experimental-websocket",
                        "--no-warnings",  std::string(SEMFUSE_SOURCE_DIR) + "/tests/viewer/page_snapshot.mjs",
                        "--chromium",     SEMFUSE_CHROMIUM_EXE,
                        "--url",          "http://127.0.0.1:" + std::to_string(port) + "/?flat=1",
                        "--png",          png,
                        "--facts",        facts_file,
                        "--blocks",       "300",
                        "--frames",       std::to_string(kFrames),
                        "--timeout-s",    "150",
                        "--ready",        ready_file,
                        "--point",        "table",
                        "-0.1",           "-0.1",
                        "0.75",           "--point",
                        "floor",          "-1.0",
                        "-0.9",           "0"});

  // The camera starts once the page is connected (Chromium may take seconds to start beside other
  // tests), so that the page sees the counter advance from the first frames.
  ASSERT_TRUE(eventually([&] { return std::ifstream(ready_file).good(); }, 150s)) << "the page never connected";
  ChildProcess camera(with({SEMFUSE_CAMERA_EXE, "--source", "synthetic", "--frames", std::to_string(kFrames), "--rate",
                            "20", "--wait-server", "30"}));
  ASSERT_EQ(waitExit(camera, 120s), 0) << "semfuse-camera failed";
  ASSERT_EQ(waitExit(browser, 150s), 0) << "the page never showed the whole map (page_snapshot.mjs)";

  const PageFacts facts = readFacts(facts_file);
  EXPECT_EQ(facts.values.at("frames"), kFrames);
  // The counter advanced while the camera ran, not only at the end: a count short of the whole
  // run was shown before the last one.
  ASSERT_GE(facts.frames_seen.size(), 2u);
  EXPECT_LT(facts.frames_seen.front(), kFrames);
  EXPECT_TRUE(std::is_sorted(facts.frames_seen.begin(), facts.frames_seen.end()));
  EXPECT_GE(facts.values.at("blocks"), 300);
  EXPECT_EQ(facts.values.at("poses"), kFrames) << "one camera path point per integrated frame";

  const LabelLegend legend = *builtinLegend("synthetic");
  for (const char* name : {"floor", "wall", "table", "chair"}) {
    bool listed = false;
    for (const std::string& row : facts.legend) listed = listed || row.rfind(std::string(name) + " ", 0) == 0;
    EXPECT_TRUE(listed) << name << " is missing from the page's legend";
  }

  // A click on the table top: labels_at answers there with the table and its confidence.
  bool table = false;
  for (const std::string& row : facts.probe) table = table || row.rfind("label table (4)", 0) == 0;
  EXPECT_TRUE(table) << "the page's answer to a click on the table: " << ::testing::PrintToString(facts.probe);
  // ... and the object there: the table (1.2 x 0.8 m top) as one instance.
  bool object = false;
  for (const std::string& row : facts.probe) {
    double x = 0, y = 0;
    if (row.rfind("object #", 0) == 0 && std::sscanf(row.c_str(), "object #%*d: %*d voxels, %lf x %lf", &x, &y) == 2)
      object = std::abs(x - 1.2) < 0.15 && std::abs(y - 0.8) < 0.15;
  }
  EXPECT_TRUE(object) << "no table-sized object at the click: " << ::testing::PrintToString(facts.probe);

  // The same click asks the server for a raycast from the page's view (320 pixels wide, labels in
  // legend colours): the table and the floor are in it.
  EXPECT_EQ(facts.raycast_size.width, 320);
  EXPECT_GT(facts.raycast_size.height, 100);
  auto raycastPixels = [&](LabelId id) {
    const auto rgb = legend.colorOf(id);
    const auto it = facts.raycast_colors.find({rgb[0], rgb[1], rgb[2]});
    return it == facts.raycast_colors.end() ? 0 : it->second;
  };
  EXPECT_GE(raycastPixels(4), 300) << "table pixels in the raycast";
  EXPECT_GE(raycastPixels(1), 3000) << "floor pixels in the raycast";

  const cv::Mat image = cv::imread(png, cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty()) << png;
  EXPECT_GE(shareAround(image, facts.points.at("table"), bgr(legend, 4)), 0.8)
      << "table top at " << facts.points.at("table");
  EXPECT_GE(shareAround(image, facts.points.at("floor"), bgr(legend, 1)), 0.8)
      << "floor at " << facts.points.at("floor");
  // Each large object of the room covers a good part of the picture in its legend colour.
  const std::map<LabelId, int> least{{1, 20000}, {2, 5000}, {4, 3000}, {5, 1000}};
  for (const auto& [id, pixels] : least) EXPECT_GE(countColor(image, bgr(legend, id)), pixels) << legend.find(id)->name;

  EXPECT_EQ(viewer.stop(), 0);
  segmenter.stop();
  EXPECT_EQ(h.stopServer(), 0);
}
