#pragma once
// WebServer: the viewer's HTTP + WebSocket endpoint (Boost.Beast, one I/O thread). GET serves
// the page's files from one folder (and "/" as index.html) and /api/<name> from a handler; a
// WebSocket upgrade on /ws opens a WebSocketSession that the viewer pushes the map to. Sessions
// send from any thread (queued in order on the I/O thread); a session whose queue grows past
// its bound is closed rather than let the viewer's memory grow with a slow browser.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace semfuse::viewer {

class WebSocketSession {
 public:
  virtual ~WebSocketSession() = default;
  // Queues a message; thread-safe, in order. Text (JSON) or binary.
  virtual void send(std::shared_ptr<const std::string> message, bool binary) = 0;
};

class WebServer {
 public:
  struct Handlers {
    // A browser connected to /ws (I/O thread).
    std::function<void(const std::shared_ptr<WebSocketSession>&)> opened;
    // It closed or failed (I/O thread).
    std::function<void(const WebSocketSession*)> closed;
    // A text message from the browser (I/O thread: answer quickly or hand the work on).
    std::function<void(const std::shared_ptr<WebSocketSession>&, const std::string&)> received;
    // GET /api/<name>: JSON, or nullopt for 404 (I/O thread).
    std::function<std::optional<std::string>(const std::string& name)> api;
  };

  // Listens on address:port (port 0: one the system picks; see port()). Throws on failure.
  WebServer(const std::string& address, uint16_t port, std::filesystem::path web_root, Handlers handlers);
  ~WebServer();  // stops
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  uint16_t port() const;
  void start();  // the I/O thread
  void stop();

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
};

}  // namespace semfuse::viewer
