#include "web_server.hpp"

#include <deque>
#include <fstream>
#include <sstream>
#include <thread>
#include <utility>

#include <spdlog/spdlog.h>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace semfuse::viewer {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

// A browser that falls this far behind is dropped.
constexpr std::size_t kMaxQueuedBytes = std::size_t{512} << 20;

std::string contentType(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".png") return "image/png";
  return "application/octet-stream";
}

class Session final : public WebSocketSession, public std::enable_shared_from_this<Session> {
 public:
  Session(tcp::socket socket, const WebServer::Handlers& handlers) : ws_(std::move(socket)), handlers_(handlers) {}

  void accept(http::request<http::string_body> request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return spdlog::debug("viewer: websocket accept: {}", ec.message());
      self->open_ = true;
      if (self->handlers_.opened) self->handlers_.opened(self);
      self->read();
    });
  }

  void send(std::shared_ptr<const std::string> message, bool binary) override {
    net::post(ws_.get_executor(), [self = shared_from_this(), message = std::move(message), binary]() mutable {
      if (!self->open_) return;
      self->queued_bytes_ += message->size();
      if (self->queued_bytes_ > kMaxQueuedBytes) {
        spdlog::warn("viewer: a browser fell {} MiB behind; closing its connection", self->queued_bytes_ >> 20);
        self->close();
        return;
      }
      self->queue_.emplace_back(std::move(message), binary);
      if (self->queue_.size() == 1) self->write();
    });
  }

 private:
  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      if (self->ws_.got_text() && self->handlers_.received)
        self->handlers_.received(self, beast::buffers_to_string(self->buffer_.data()));
      self->buffer_.consume(self->buffer_.size());
      self->read();
    });
  }

  void write() {
    auto& [message, binary] = queue_.front();
    ws_.binary(binary);
    ws_.async_write(net::buffer(*message), [self = shared_from_this()](beast::error_code ec, std::size_t bytes) {
      if (ec) return self->close();
      self->queued_bytes_ -= std::min(self->queued_bytes_, bytes);
      self->queue_.pop_front();
      if (!self->queue_.empty()) self->write();
    });
  }

  void close() {
    if (!open_) return;
    open_ = false;
    queue_.clear();
    if (handlers_.closed) handlers_.closed(this);
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
  }

  websocket::stream<beast::tcp_stream> ws_;
  const WebServer::Handlers& handlers_;
  beast::flat_buffer buffer_;
  std::deque<std::pair<std::shared_ptr<const std::string>, bool>> queue_;
  std::size_t queued_bytes_ = 0;
  bool open_ = false;
};

class HttpConnection : public std::enable_shared_from_this<HttpConnection> {
 public:
  HttpConnection(tcp::socket socket, const std::filesystem::path& root, const WebServer::Handlers& handlers)
      : stream_(std::move(socket)), root_(root), handlers_(handlers) {}

  void read() {
    request_ = {};
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, request_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return;
      self->handle();
    });
  }

 private:
  void handle() {
    if (websocket::is_upgrade(request_)) {
      if (request_.target() != "/ws") return respond(http::status::not_found, "text/plain", "no such socket");
      stream_.expires_never();
      std::make_shared<Session>(stream_.release_socket(), handlers_)->accept(std::move(request_));
      return;
    }
    if (request_.method() != http::verb::get && request_.method() != http::verb::head)
      return respond(http::status::method_not_allowed, "text/plain", "GET only");
    std::string target(request_.target());
    if (const auto query = target.find('?'); query != std::string::npos) target.resize(query);
    if (target.rfind("/api/", 0) == 0) {
      auto json = handlers_.api ? handlers_.api(target.substr(5)) : std::nullopt;
      if (!json) return respond(http::status::not_found, "text/plain", "no such API");
      return respond(http::status::ok, "application/json", std::move(*json));
    }
    if (target == "/") target = "/index.html";
    // Only plain names inside the page's folder.
    if (target.find("..") != std::string::npos || target.find('\\') != std::string::npos)
      return respond(http::status::bad_request, "text/plain", "bad path");
    const std::filesystem::path file = root_ / target.substr(1);
    std::ifstream in(file, std::ios::binary);
    if (!in) return respond(http::status::not_found, "text/plain", "not found: " + target);
    std::ostringstream body;
    body << in.rdbuf();
    respond(http::status::ok, contentType(file), body.str());
  }

  void respond(http::status status, const std::string& type, std::string body) {
    auto response = std::make_shared<http::response<http::string_body>>(status, request_.version());
    response->set(http::field::server, "semfuse-viewer");
    response->set(http::field::content_type, type);
    response->set(http::field::cache_control, "no-cache");
    response->keep_alive(request_.keep_alive());
    response->body() = std::move(body);
    response->prepare_payload();
    http::async_write(stream_, *response, [self = shared_from_this(), response](beast::error_code ec, std::size_t) {
      if (ec || !response->keep_alive()) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
      }
      self->read();
    });
  }

  beast::tcp_stream stream_;
  const std::filesystem::path& root_;
  const WebServer::Handlers& handlers_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
};

}  // namespace

struct WebServer::Impl {
  Impl(const std::string& address, uint16_t port, std::filesystem::path root, Handlers h)
      : web_root(std::move(root)), handlers(std::move(h)), acceptor(io) {
    const tcp::endpoint endpoint(net::ip::make_address(address), port);
    acceptor.open(endpoint.protocol());
    acceptor.set_option(net::socket_base::reuse_address(true));
    acceptor.bind(endpoint);
    acceptor.listen();
  }

  void accept() {
    acceptor.async_accept(net::make_strand(io), [this](beast::error_code ec, tcp::socket socket) {
      if (ec) {
        if (ec != net::error::operation_aborted) spdlog::warn("viewer: accept: {}", ec.message());
        if (!acceptor.is_open()) return;
      } else {
        std::make_shared<HttpConnection>(std::move(socket), web_root, handlers)->read();
      }
      accept();
    });
  }

  std::filesystem::path web_root;
  Handlers handlers;
  net::io_context io{1};
  tcp::acceptor acceptor;
  std::thread thread;
};

WebServer::WebServer(const std::string& address, uint16_t port, std::filesystem::path web_root, Handlers handlers)
    : impl_(std::make_shared<Impl>(address, port, std::move(web_root), std::move(handlers))) {}

WebServer::~WebServer() { stop(); }

uint16_t WebServer::port() const { return impl_->acceptor.local_endpoint().port(); }

void WebServer::start() {
  impl_->accept();
  impl_->thread = std::thread([impl = impl_] { impl->io.run(); });
}

void WebServer::stop() {
  if (!impl_->thread.joinable()) return;
  impl_->io.stop();
  impl_->thread.join();
}

}  // namespace semfuse::viewer
