#include "src/app/serve.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "src/app/app_failure.h"
#include "src/app/run_steps.h"
#include "src/app/stop_signals.h"
#include "src/io/model_scene.h"
#include "src/io/scene_loader.h"
#include "src/server/http_server.h"
#include "src/server/live_render.h"

namespace pt {
namespace {

bool IsLoopback(const std::string& address) {
  return address == "127.0.0.1" || address == "::1" || address == "localhost";
}

SceneDocument LoadDocument(const CliOptions& cli, const RenderSettings& render) {
  try {
    return SceneDocument(cli.scenePath, render);
  } catch (const std::exception& e) {
    throw AppFailure{kExitBadInput, e.what()};
  }
}

}  // namespace

int Serve(const CliOptions& cli, const AppBackends& backends) {
  // The preview edits a JSON document; a model file is rendered whole only by a plain render.
  if (IsModelFile(cli.scenePath)) {
    throw AppFailure{kExitBadInput,
                     cli.scenePath + ": --serve previews JSON scenes: include the model in one "
                     "as {\"type\": \"mesh\", \"file\": \"" + cli.scenePath + "\"} (with "
                     "\"background\": [1, 1, 1] for the default environment; docs/serve.md)"};
  }
  if (!backends.startServer) {
    throw AppFailure{kExitRuntimeFailure,
                     "--serve: this build has no preview server (install libcpp-httplib-dev "
                     "and configure again; see docs/serve.md)"};
  }
  double loadMs = 0.0, bvhMs = 0.0;
  SceneDesc desc = LoadAndOverride(cli, &loadMs);
  SceneDocument document = LoadDocument(cli, desc.render);
  Scene scene = Build(std::move(desc), ChooseBvh(cli, backends), &bvhMs);
  BackendKind backend = ChooseBackend(cli.backend, backends);
  LiveSettings settings;
  settings.options = MakeRenderOptions(cli, backend, nullptr);
  SessionFactory factory = backend == BackendKind::kCuda ? backends.cudaSession
                                                         : backends.cpuSession;
  // The page's denoise toggle: the render backend's denoiser, made by the preview.
  DenoiserFactory makeDenoiser = backend == BackendKind::kCuda ? backends.cudaDenoiser
                                                               : backends.cpuDenoiser;
  if (makeDenoiser) {
    int where = backend == BackendKind::kCuda ? settings.options.device : cli.threads;
    settings.makeDenoiser = [makeDenoiser, where] { return makeDenoiser(where, DenoiseSettings{}); };
    settings.denoise = cli.denoise;
  }
  LiveRender live(std::move(document), std::move(scene), factory, settings);

  HttpServerConfig config;
  if (!cli.bindAddress.empty()) config.bind = cli.bindAddress;
  config.port = *cli.servePort;
  std::signal(SIGPIPE, SIG_IGN);  // a browser that goes away mid-answer must not end us
  std::unique_ptr<HttpServer> server;
  try {
    server = backends.startServer(live, config);
  } catch (const std::exception& e) {
    throw AppFailure{kExitRuntimeFailure, std::string("--serve: ") + e.what()};
  }
  std::string host = config.bind.find(':') != std::string::npos ? "[" + config.bind + "]"
                                                                 : config.bind;
  std::fprintf(stderr, "pathtracer: serving %s on http://%s:%d/ (Ctrl-C stops)\n",
               cli.scenePath.c_str(), host.c_str(), server->Port());
  if (!IsLoopback(config.bind)) {
    Warn("--bind " + config.bind + ": anyone who can reach this address can watch and edit "
         "the render (docs/serve.md shows SSH port forwarding instead)");
  }
  InstallStopSignals();
  while (!StopSignal()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  server->Stop();
  live.Stop();
  std::fprintf(stderr, "pathtracer: %s received: the preview stopped\n",
               SignalName(StopSignal()).c_str());
  return kExitOk;
}

}  // namespace pt
