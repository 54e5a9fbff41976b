// The preview's HTTP API as plain functions of a request, so that it is tested and reasoned
// about without a socket; src/server/http_server.cpp only carries requests to it.
//
//   GET  /api/events                the page's event stream (text/event-stream): "scene",
//                                   "state" and "progress" events, each a JSON document,
//                                   all three at once on connecting, then each as it changes
//   GET  /api/scene                 objects, materials, cameras, maps, render settings (JSON)
//   GET  /api/state                 camera, options, display, selection, lighting (JSON)
//   GET  /api/progress              the latest frame's statistics and the render's state
//   GET  /api/frame?after=ID        the next frame newer than ID (JPEG; waits up to 2 s)
//   GET  /api/stats                 the latest frame's statistics (JSON)
//   GET  /api/outline.png?max=N     the selected object's outline (RGBA PNG; 204: none)
//   GET  /api/image.png|.exr        the current image (attachment; the PNG as displayed)
//   GET  /api/scene.json            the edited scene file (attachment)
//   POST /api/camera                {position, look_at, up, fov_y, ...}: merged into the
//                                   camera; {choose: N}: an offered camera; {frame: "selection"}
//   POST /api/options               {compact, sort, integrator, specialize, light_sampler,
//                                   max_depth, spp, denoise}
//   POST /api/lighting              {map, strength, rotation}
//   POST /api/pick                  {x, y} in pixels: the object and material seen there
//   POST /api/select                {x, y}: select what is seen there; {object: null}: none
//   POST /api/objects/N/move        {translate: [dx, dy, dz]}
//   POST /api/materials/N           material fields, as in the scene file
//   POST /api/display               {exposure, tone_mapping}: display only
// Edits answer {"generation": G, "restarts": bool}: frames of generation >= G show them.
// Errors answer {"error": "...", "field": "..."} with a 4xx status; nothing a client sends
// stops the render.
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "src/server/change_feed.h"

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

ApiResponse ErrorResponse(int status, const std::string& message, const std::string& field = "");

// Where a page's event stream stands: the versions it has seen.
struct EventCursor {
  bool started = false;
  ChangeFeed::Versions seen{};
};

// The events a page has not seen yet (server-sent events text), waiting up to `wait` for one;
// empty when none came (the stream then sends a keep-alive comment).
std::string NextEvents(LiveRender& live, EventCursor& cursor, std::chrono::milliseconds wait);

// Answers a request under /api/.
ApiResponse HandleApi(LiveRender& live, const ApiRequest& request);

// Whether a Host header names this server in a way no DNS rebinding can fake: "localhost",
// a loopback or the bound address as an IP literal ("[...]" for IPv6), with the server's
// port. A server bound to every address (0.0.0.0 or ::) accepts any IP literal.
bool HostAllowed(const std::string& host, const std::string& bindAddress, int port);

// Whether an Origin header (empty when the browser sent none) is this server's own page.
bool OriginAllowed(const std::string& origin, const std::string& host);

}  // namespace pt
