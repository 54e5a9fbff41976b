// The preview's HTTP API as plain functions of a request, so that it is tested and reasoned
// about without a socket; src/server/http_server.cpp only carries requests to it.
//
//   GET  /api/scene                 objects, materials, camera, render settings, flags (JSON)
//   GET  /api/frame?after=ID        the next frame newer than ID (JPEG; waits up to 2 s)
//   GET  /api/stats                 the latest frame's statistics (JSON)
//   GET  /api/image.png|.exr        the current image (attachment)
//   GET  /api/scene.json            the edited scene file (attachment)
//   POST /api/camera                {position, look_at, up, fov_y, ...}: merged into the camera
//   POST /api/options               {compact, sort, integrator, specialize, max_depth, spp}
//   POST /api/pick                  {x, y} in pixels: the object and material seen there
//   POST /api/objects/N/move        {translate: [dx, dy, dz]}
//   POST /api/materials/N           material fields, as in the scene file
//   POST /api/display               {exposure}: stops, display only
// Edits answer {"generation": G}: frames of generation >= G show them. Errors answer
// {"error": "..."} with a 4xx status; nothing a client sends stops the render.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace pt {

class LiveRender;

inline constexpr int kDefaultServePort = 8765;
inline constexpr size_t kMaxRequestBodyBytes = 64 * 1024;

struct ApiRequest {
  std::string method;  // "GET", "POST", ...
  std::string path;    // without the query
  std::map<std::string, std::string> query;
  std::string contentType;
  std::string body;
};

struct ApiResponse {
  int status = 200;
  std::string contentType = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

ApiResponse ErrorResponse(int status, const std::string& message);

// Answers a request under /api/.
ApiResponse HandleApi(LiveRender& live, const ApiRequest& request);

// Whether a Host header names this server in a way no DNS rebinding can fake: "localhost",
// a loopback or the bound address as an IP literal ("[...]" for IPv6), with the server's
// port. A server bound to every address (0.0.0.0 or ::) accepts any IP literal.
bool HostAllowed(const std::string& host, const std::string& bindAddress, int port);

// Whether an Origin header (empty when the browser sent none) is this server's own page.
bool OriginAllowed(const std::string& origin, const std::string& host);

}  // namespace pt
