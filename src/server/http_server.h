// The preview's HTTP server (cpp-httplib, an optional component: built only when
// libcpp-httplib-dev is found at configure time). It serves the page embedded from web/ and the
// API of src/server/api.h, nothing else: no path from a client ever reaches the file system.
#pragma once

#include <memory>
#include <string>

#include "src/server/api.h"

namespace pt {

struct HttpServerConfig {
  std::string bind = "127.0.0.1";  // loopback unless the user names another address
  int port = kDefaultServePort;    // 0: any free port (tests)
  size_t threads = 64;  // each watching page holds one for its frame long-poll
};

class HttpServer {
 public:
  virtual ~HttpServer() = default;
  virtual int Port() const = 0;  // the bound port
  virtual void Stop() = 0;
};

// Binds and serves on threads of its own. Throws std::runtime_error when it cannot bind.
std::unique_ptr<HttpServer> StartHttpServer(LiveRender& live, const HttpServerConfig& config);

// A file of web/ by its URL path ("/" is index.html); null for anything else.
struct WebAsset {
  const char* path;
  const char* contentType;
  const unsigned char* data;
  size_t size;
};
const WebAsset* FindWebAsset(const std::string& urlPath);

}  // namespace pt
