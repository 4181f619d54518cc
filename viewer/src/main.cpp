// semfuse-viewer: follows a semfuse server's live mesh over DDS and serves it as a web page
// (HTTP + WebSocket): the labeled mesh as it grows, coloured by label, RGB or confidence, the
// legend with counts, each camera's frustum and path, the server's counters, and the label at a
// clicked point.
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "semfuse/cli/command_line.hpp"
#include "semfuse/cli/exit_codes.hpp"
#include "semfuse/cli/stop_signal.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/client/map_follower.hpp"
#include "semfuse/core/logging.hpp"
#include "semfuse/dds/participant.hpp"
#include "viewer_hub.hpp"
#include "web_server.hpp"

using namespace semfuse;

namespace {

// The page's files: --web-root, else the build tree's copy, else the installed one.
std::filesystem::path findWebRoot(const std::string& option) {
  if (!option.empty()) return option;
  for (const char* candidate : {SEMFUSE_VIEWER_BUILD_WEB_DIR, SEMFUSE_VIEWER_INSTALL_WEB_DIR})
    if (std::filesystem::exists(std::filesystem::path(candidate) / "index.html")) return candidate;
  return {};
}

// Follows the map and serves the page until Ctrl-C / SIGTERM.
int serve(const cli::CommonOptions& common, const std::string& address, uint16_t port,
          const std::filesystem::path& root, const LabelLegend& fallback) {
  dds::Participant participant(common.domain_id < 0 ? DDS_DOMAIN_DEFAULT
                                                    : static_cast<dds_domainid_t>(common.domain_id));
  client::MapClient map(participant);
  client::MapFollower follower(participant);
  viewer::ViewerHub hub(follower, map, fallback);
  follower.setListener([&hub](const client::MapFollowerChange& change) { hub.onChange(change); });

  std::unique_ptr<viewer::WebServer> web;
  try {
    web = std::make_unique<viewer::WebServer>(address, port, root, hub.handlers());
  } catch (const std::exception& e) {
    spdlog::error("cannot listen on {}:{}: {}", address, port, e.what());
    return cli::kExitFailure;
  }
  follower.start();
  web->start();
  // The one line scripts and tests read to find the page.
  std::cout << "semfuse-viewer: http://" << address << ":" << web->port() << "/" << std::endl;
  spdlog::info("serving {}", root.string());

  while (!cli::stopRequested()) hub.tick(std::chrono::milliseconds(100));

  web->stop();
  follower.stop();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Serves a live web view of a semfuse map server's map (open the printed address in a browser).",
               "semfuse-viewer"};
  cli::CommonOptions common;
  cli::addCommonOptions(app, common);
  std::string address = "127.0.0.1";
  uint16_t port = 8090;
  std::string web_root;
  std::string legend_name = "ade20k";
  app.add_option("--address", address, "address to listen on (0.0.0.0: every interface)")->capture_default_str();
  app.add_option("--port", port, "HTTP port (0: one the system picks, printed)")->capture_default_str();
  app.add_option("--web-root", web_root, "folder of the page's files (default: the build's or the installed copy)");
  app.add_option("--legend", legend_name, "legend for names and colours until the server publishes its own")
      ->capture_default_str();
  if (const int code = cli::parseCommandLine(app, argc, argv); code >= 0) return code;
  if (Status logging = setupLogging("semfuse-viewer", common.log_level); !logging) {
    spdlog::error("{}", logging.error());
    return cli::kExitUsage;
  }

  const std::filesystem::path root = findWebRoot(web_root);
  if (root.empty() || !std::filesystem::exists(root / "index.html")) {
    spdlog::error("no page to serve: {} has no index.html (--web-root)", root.empty() ? "(none found)" : root.string());
    return cli::kExitUsage;
  }
  auto fallback = builtinLegend(legend_name);
  if (!fallback) {
    spdlog::error("unknown legend '{}'", legend_name);
    return cli::kExitUsage;
  }

  cli::installStopHandler();
  try {
    return serve(common, address, port, root, *fallback);
  } catch (const std::exception& e) {  // DDS entities that cannot be created (bad profile, security)
    spdlog::error("{}", e.what());
    return cli::kExitFailure;
  }
}
