#include "src/server/http_server.h"

#include <httplib.h>

#include <chrono>
#include <memory>
#include <stdexcept>
#include <thread>

#include "src/server/live_render.h"

namespace pt {
namespace {

constexpr time_t kTimeoutSeconds = 5;
constexpr auto kEventWait = std::chrono::milliseconds(250);
constexpr int kKeepAliveEvery = 40;  // quiet waits: a comment every 10 s

void Send(const ApiResponse& api, httplib::Response& res) {
  res.status = api.status;
  for (const auto& [name, value] : api.headers) res.set_header(name, value);
  res.set_content(api.body, api.contentType);
}

// Every answer: no caching, no sniffing, no framing, scripts only from this server.
const httplib::Headers& SafetyHeaders() {
  static const httplib::Headers headers = {
      {"Cache-Control", "no-store"},
      {"X-Content-Type-Options", "nosniff"},
      {"X-Frame-Options", "DENY"},
      {"Referrer-Policy", "no-referrer"},
      {"Content-Security-Policy",
       "default-src 'self'; img-src 'self' blob:; style-src 'self'; script-src 'self'; "
       "connect-src 'self'; frame-ancestors 'none'"}};
  return headers;
}

// Messages for the errors httplib answers before a handler runs.
std::string StatusMessage(int status) {
  switch (status) {
    case 400: return "malformed request";
    case 404: return "no such resource";
    case 413: return "request too large (bodies up to " + std::to_string(kMaxRequestBodyBytes) + " bytes)";
    case 414: return "request URI too long";
    default: return "request refused (HTTP " + std::to_string(status) + ")";
  }
}

class HttplibServer final : public HttpServer {
 public:
  HttplibServer(LiveRender& live, const HttpServerConfig& config) : live_(live), config_(config) {
    size_t threads = config.threads;
    server_.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    server_.set_payload_max_length(kMaxRequestBodyBytes);
    server_.set_read_timeout(kTimeoutSeconds, 0);
    server_.set_write_timeout(kTimeoutSeconds, 0);
    server_.set_keep_alive_timeout(2);
    server_.set_default_headers(SafetyHeaders());
    server_.set_pre_routing_handler(
        [this](const httplib::Request& req, httplib::Response& res) { return Check(req, res); });
    server_.Get("/api/events", [this](const httplib::Request&, httplib::Response& res) {
      Events(res);
    });
    auto api = [this](const httplib::Request& req, httplib::Response& res) { Api(req, res); };
    server_.Get("/api/.*", api);
    server_.Post("/api/.*", api);
    server_.Get(".*", [](const httplib::Request& req, httplib::Response& res) {
      const WebAsset* asset = FindWebAsset(req.path);
      if (!asset) return Send(ErrorResponse(404, "no such page: " + req.path), res);
      res.set_content(reinterpret_cast<const char*>(asset->data), asset->size, asset->contentType);
    });
    server_.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
      if (res.body.empty()) {
        Send(ErrorResponse(res.status, StatusMessage(res.status)), res);
      }
    });
    server_.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr e) {
          std::string what = "internal error";
          try {
            std::rethrow_exception(e);
          } catch (const std::exception& ex) {
            what = ex.what();
          } catch (...) {
          }
          Send(ErrorResponse(500, what), res);
        });
    port_ = config.port == 0 ? server_.bind_to_any_port(config.bind)
                             : (server_.bind_to_port(config.bind, config.port) ? config.port : -1);
    if (port_ <= 0) {
      throw std::runtime_error("cannot listen on " + config.bind + ":" +
                               std::to_string(config.port) +
                               " (in use, or not an address of this machine)");
    }
    thread_ = std::thread([this] { server_.listen_after_bind(); });
  }

  ~HttplibServer() override { Stop(); }

  int Port() const override { return port_; }

  void Stop() override {
    server_.stop();
    if (thread_.joinable()) thread_.join();
  }

 private:
  // Before any route: the Host header (against DNS rebinding), the Origin of anything that
  // is not a plain read, and the methods this server has.
  httplib::Server::HandlerResponse Check(const httplib::Request& req, httplib::Response& res) {
    std::string host = req.get_header_value("Host");
    if (!HostAllowed(host, config_.bind, port_)) {
      Send(ErrorResponse(403, "Host \"" + host + "\" is not this server (use http://127.0.0.1:" +
                                  std::to_string(port_) + "/)"),
           res);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.method != "GET" && req.method != "HEAD" &&
        !OriginAllowed(req.get_header_value("Origin"), host)) {
      Send(ErrorResponse(403, "requests from other pages are refused"), res);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.method != "GET" && req.method != "HEAD" && req.method != "POST") {
      Send(ErrorResponse(405, "method " + req.method + " is not allowed"), res);
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  }

  // Server-sent events: each call of the provider waits up to kEventWait for a change (so
  // a stopping server ends the stream soon), a comment now and then finds clients gone.
  void Events(httplib::Response& res) {
    auto cursor = std::make_shared<EventCursor>();
    auto quiet = std::make_shared<int>(0);
    res.set_chunked_content_provider(
        "text/event-stream", [this, cursor, quiet](size_t, httplib::DataSink& sink) {
          if (live_.Feed().Closed()) {
            sink.done();
            return true;
          }
          std::string text = NextEvents(live_, *cursor, kEventWait);
          if (text.empty() && ++*quiet % kKeepAliveEvery == 0) text = ": keep-alive\n\n";
          if (text.empty()) return true;
          *quiet = 0;
          return sink.write(text.data(), text.size());
        });
  }

  void Api(const httplib::Request& req, httplib::Response& res) {
    ApiRequest request;
    request.method = req.method;
    request.path = req.path;
    for (const auto& [key, value] : req.params) request.query[key] = value;
    request.contentType = req.get_header_value("Content-Type");
    request.body = req.body;
    Send(HandleApi(live_, request), res);
  }

  LiveRender& live_;
  HttpServerConfig config_;
  httplib::Server server_;
  int port_ = -1;
  std::thread thread_;
};

}  // namespace

std::unique_ptr<HttpServer> StartHttpServer(LiveRender& live, const HttpServerConfig& config) {
  return std::make_unique<HttplibServer>(live, config);
}

}  // namespace pt
