#include "src/server/api.h"

#include <arpa/inet.h>

#include <charconv>

#include "src/io/image_io.h"
#include "src/io/tone_mapping.h"
#include "src/server/live_render.h"

namespace pt {
namespace {

constexpr auto kFrameWait = std::chrono::milliseconds(2000);

ApiResponse JsonResponse(const Json& body) {
  ApiResponse r;
  r.body = body.dump();
  return r;
}

Json ParseBody(const ApiRequest& request) {
  if (request.contentType.rfind("application/json", 0) != 0) {
    // Also what keeps a page of another site from posting here: a cross-site request with
    // this content type needs a CORS preflight, which this server never grants.
    throw EditError(415, "POST bodies must be application/json");
  }
  Json body = Json::parse(request.body, nullptr, false);
  if (body.is_discarded()) throw EditError(400, "the body is not valid JSON");
  return body;
}

// A non-negative decimal index, or -1.
int64_t ParseIndex(const std::string& text) {
  int64_t value = -1;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || value < 0) return -1;
  return value;
}

vec3 Vec3Field(const Json& body, const char* key) {
  if (!body.is_object() || !body.contains(key) || !body[key].is_array() || body[key].size() != 3) {
    throw EditError(400, std::string("expected {\"") + key + "\": [x, y, z]}");
  }
  vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!body[key][size_t(i)].is_number()) throw EditError(400, std::string(key) + " needs numbers");
    v[i] = body[key][size_t(i)].get<float>();
  }
  return v;
}

float NumberField(const Json& body, const char* key) {
  if (!body.is_object() || !body.contains(key) || !body[key].is_number()) {
    throw EditError(400, std::string("expected a number \"") + key + "\"");
  }
  return body[key].get<float>();
}

ApiResponse FrameResponse(LiveRender& live, const ApiRequest& request) {
  int64_t after = 0;
  auto it = request.query.find("after");
  if (it != request.query.end() && (after = ParseIndex(it->second)) < 0) {
    return ErrorResponse(400, "after must be a frame id");
  }
  std::shared_ptr<const PreviewFrame> frame = live.WaitForFrame(uint64_t(after), kFrameWait);
  if (!frame || frame->id <= uint64_t(after)) return ApiResponse{204, "text/plain", "", {}};
  ApiResponse r;
  r.contentType = "image/jpeg";
  r.body = frame->jpeg;
  r.headers = {{"X-Frame-Id", std::to_string(frame->id)},
               {"X-Generation", std::to_string(frame->generation)},
               {"X-Spp", std::to_string(frame->spp)},
               {"X-Frame-Kind", frame->kind},
               {"X-Width", std::to_string(frame->width)},
               {"X-Height", std::to_string(frame->height)}};
  return r;
}

ApiResponse Download(std::string body, const std::string& type, const std::string& name) {
  ApiResponse r;
  r.contentType = type;
  r.body = std::move(body);
  r.headers = {{"Content-Disposition", "attachment; filename=\"" + name + "\""}};
  return r;
}

// The PNG is what the page shows (exposure, tone mapping, denoising); the EXR stays linear
// (with the denoised layer when it has one).
ApiResponse ImageDownload(LiveRender& live, ImageFormat format) {
  std::shared_ptr<const FilmImage> image = live.LatestImage();
  if (!image) return ErrorResponse(503, "no image yet");
  if (format == ImageFormat::kPng) {
    bool denoised = live.Denoising() && !image->denoised.empty();
    return Download(EncodePng8("preview.png", image->width, image->height,
                               DisplayPixels(denoised ? image->denoised : image->rgb,
                                             live.Display())),
                    "image/png", "preview.png");
  }
  return Download(EncodeImage("preview", *image, format, true), "image/x-exr", "preview.exr");
}

ApiResponse Answer(const EditAnswer& a) {
  return JsonResponse(Json{{"generation", a.generation}, {"restarts", a.restarts}});
}

ApiResponse Get(LiveRender& live, const ApiRequest& request) {
  const std::string& p = request.path;
  if (p == "/api/scene") return ApiResponse{200, "application/json", live.DescribeJson(), {}};
  if (p == "/api/state") return ApiResponse{200, "application/json", live.StateJson(), {}};
  if (p == "/api/progress") return ApiResponse{200, "application/json", live.ProgressJson(), {}};
  if (p == "/api/frame") return FrameResponse(live, request);
  if (p == "/api/stats") {
    std::shared_ptr<const PreviewFrame> frame = live.LatestFrame();
    if (!frame) return ErrorResponse(503, "no frame yet");
    return ApiResponse{200, "application/json", frame->statsJson, {}};
  }
  if (p == "/api/outline.png") {
    auto it = request.query.find("max");
    int64_t side = it == request.query.end() ? 320 : ParseIndex(it->second);
    if (side < 1 || side > 4096) return ErrorResponse(400, "max must be a side in [1, 4096]");
    std::string png = live.OutlinePng(int(side));
    if (png.empty()) return ApiResponse{204, "text/plain", "", {}};
    return ApiResponse{200, "image/png", std::move(png), {}};
  }
  if (p == "/api/image.png") return ImageDownload(live, ImageFormat::kPng);
  if (p == "/api/image.exr") return ImageDownload(live, ImageFormat::kExr);
  if (p == "/api/scene.json") return Download(live.SceneText(), "application/json", "scene.json");
  return ErrorResponse(404, "no such resource: GET " + p);
}

// {"choose": N}: one of the offered cameras; {"frame": "selection"}: fit the selected object;
// anything else: camera fields merged into the camera.
ApiResponse PostCamera(LiveRender& live, const Json& body) {
  if (body.is_object() && body.contains("choose")) {
    if (body.size() != 1) return ErrorResponse(400, "choose goes alone");
    int64_t index = body["choose"].is_number_integer() ? body["choose"].get<int64_t>() : -1;
    if (index < 0) return ErrorResponse(400, "choose needs a camera index");
    return Answer(live.ChooseCamera(size_t(index)));
  }
  if (body.is_object() && body.contains("frame")) {
    if (body.size() != 1 || body["frame"] != "selection") {
      return ErrorResponse(400, "expected {\"frame\": \"selection\"}");
    }
    return Answer(live.FrameSelected());
  }
  return Answer(live.EditCamera(body));
}

// {"x", "y"}: the object seen at that pixel becomes the selection; {"object": null}: none.
ApiResponse PostSelect(LiveRender& live, const Json& body) {
  if (body.is_object() && body.contains("object") && body["object"].is_null()) {
    live.Select(-1, -1);
    return JsonResponse(Json{{"object", nullptr}, {"material", nullptr}});
  }
  PickResult hit = live.Pick(NumberField(body, "x"), NumberField(body, "y"));
  live.Select(hit.object, hit.material);
  Json j{{"object", nullptr}, {"material", nullptr}};
  if (hit.object >= 0) j["object"] = hit.object;
  if (hit.material >= 0 && hit.object >= 0) j["material"] = hit.material;
  return JsonResponse(j);
}

ApiResponse Post(LiveRender& live, const ApiRequest& request) {
  const std::string& p = request.path;
  const std::string objects = "/api/objects/", materials = "/api/materials/";
  if (p == "/api/camera") return PostCamera(live, ParseBody(request));
  if (p == "/api/options") return Answer(live.EditOptions(ParseBody(request)));
  if (p == "/api/lighting") return Answer(live.EditLighting(ParseBody(request)));
  if (p == "/api/select") return PostSelect(live, ParseBody(request));
  if (p == "/api/display") {
    live.EditDisplay(ParseBody(request));
    return JsonResponse(Json::object());
  }
  if (p == "/api/pick") {
    Json body = ParseBody(request);
    PickResult hit = live.Pick(NumberField(body, "x"), NumberField(body, "y"));
    Json j{{"object", nullptr}, {"material", nullptr}};
    if (hit.object >= 0) j["object"] = hit.object;
    if (hit.material >= 0) j["material"] = hit.material;
    if (hit.material >= 0) {
      j["point"] = Json::array({hit.point.x, hit.point.y, hit.point.z});
      j["distance"] = hit.distance;
    }
    return JsonResponse(j);
  }
  if (p.rfind(objects, 0) == 0 && p.size() > objects.size() + 5 &&
      p.compare(p.size() - 5, 5, "/move") == 0) {
    int64_t index = ParseIndex(p.substr(objects.size(), p.size() - objects.size() - 5));
    if (index < 0) return ErrorResponse(404, "no such object: " + p);
    return Answer(live.MoveObject(size_t(index), Vec3Field(ParseBody(request), "translate")));
  }
  if (p.rfind(materials, 0) == 0) {
    int64_t index = ParseIndex(p.substr(materials.size()));
    if (index < 0) return ErrorResponse(404, "no such material: " + p);
    return Answer(live.EditMaterial(size_t(index), ParseBody(request)));
  }
  return ErrorResponse(404, "no such resource: POST " + p);
}

bool IsIpLiteral(const std::string& name) {
  unsigned char buffer[16];
  if (name.size() > 2 && name.front() == '[' && name.back() == ']') {
    return inet_pton(AF_INET6, name.substr(1, name.size() - 2).c_str(), buffer) == 1;
  }
  return inet_pton(AF_INET, name.c_str(), buffer) == 1;
}

std::string Bracketed(const std::string& address) {
  return address.find(':') != std::string::npos ? "[" + address + "]" : address;
}

}  // namespace

ApiResponse ErrorResponse(int status, const std::string& message, const std::string& field) {
  ApiResponse r;
  r.status = status;
  Json body{{"error", message}};
  if (!field.empty()) body["field"] = field;
  r.body = body.dump();
  return r;
}

std::string NextEvents(LiveRender& live, EventCursor& cursor, std::chrono::milliseconds wait) {
  ChangeFeed::Versions now = live.Feed().Wait(cursor.seen, wait);
  std::string out;
  auto event = [&](const char* name, const std::string& data) {
    out.append("event: ").append(name).append("\ndata: ").append(data).append("\n\n");
  };
  // Everything on the first call: a page (re)loaded shows what the render uses.
  bool first = !cursor.started;
  cursor.started = true;
  if (first || now[ChangeFeed::kScene] != cursor.seen[ChangeFeed::kScene]) {
    event("scene", live.DescribeJson());
  }
  if (first || now[ChangeFeed::kState] != cursor.seen[ChangeFeed::kState]) {
    event("state", live.StateJson());
  }
  if (first || now[ChangeFeed::kProgress] != cursor.seen[ChangeFeed::kProgress]) {
    event("progress", live.ProgressJson());
  }
  cursor.seen = now;
  return out;
}

ApiResponse HandleApi(LiveRender& live, const ApiRequest& request) {
  try {
    if (request.method == "GET") return Get(live, request);
    if (request.method == "POST") return Post(live, request);
    return ErrorResponse(405, "method " + request.method + " is not allowed");
  } catch (const EditError& e) {
    return ErrorResponse(e.status, e.what(), e.field);
  } catch (const Json::exception& e) {
    return ErrorResponse(400, std::string("bad JSON value: ") + e.what());
  } catch (const ImageError& e) {
    return ErrorResponse(500, e.what());
  }
}

bool HostAllowed(const std::string& host, const std::string& bindAddress, int port) {
  // Appended rather than ":" + to_string(port): GCC 12 at -march=x86-64-v3 gives a false
  // -Wstringop-overflow on the latter.
  std::string suffix(":");
  suffix += std::to_string(port);
  if (host.size() <= suffix.size() || host.compare(host.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return false;
  }
  std::string name = host.substr(0, host.size() - suffix.size());
  for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (name == "localhost" || name == "127.0.0.1" || name == "[::1]") return true;
  if (!IsIpLiteral(name)) return false;  // a DNS name could be rebound to this machine
  if (bindAddress == "0.0.0.0" || bindAddress == "::") return true;
  return name == Bracketed(bindAddress);
}

bool OriginAllowed(const std::string& origin, const std::string& host) {
  return origin.empty() || origin == "http://" + host;
}

}  // namespace pt
