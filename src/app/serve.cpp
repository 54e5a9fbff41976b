#include "src/app/serve.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "src/app/app_failure.h"
#include "src/app/denoise_step.h"
#include "src/app/outputs.h"
#include "src/app/run_steps.h"
#include "src/app/stop_signals.h"
#include "src/io/gltf_loader.h"
#include "src/io/image_io.h"
#include "src/io/model_scene.h"
#include "src/io/scene_loader.h"
#include "src/server/http_server.h"
#include "src/server/live_render.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

bool IsLoopback(const std::string& address) {
  return address == "127.0.0.1" || address == "::1" || address == "localhost";
}

// The document the page edits: the JSON scene file, or for a model file the JSON scene that
// includes it (its camera and lighting as the load gave them). `loaded` is the scene as built.
SceneDocument LoadDocument(const CliOptions& cli, const SceneDesc& loaded) {
  try {
    if (IsModelFile(cli.scenePath)) {
      return SceneDocument::ForModel(cli.scenePath, loaded, CliLoadOptions(cli));
    }
    SceneDocument document(cli.scenePath, loaded.render);
    // --env, --env none, --env-strength: the document states the lighting rendered.
    if (!cli.envPath.empty() || cli.envStrength) document.AdoptLighting(loaded);
    return document;
  } catch (const std::exception& e) {
    throw AppFailure{kExitBadInput, e.what()};
  }
}

// The perspective cameras a glTF file places, offered beside the scene's own: the model's
// when the scene is a model file, or the file a JSON scene's camera comes from.
std::vector<NamedCamera> FileCameras(const CliOptions& cli, const SceneDocument& document) {
  std::string file;
  if (IsModelFile(cli.scenePath)) {
    file = cli.scenePath;
  } else if (document.CameraJson().contains("from_file")) {
    file = document.CameraJson()["from_file"].get<std::string>();
  }
  std::string ext = LowerExtension(file);
  if (ext != ".gltf" && ext != ".glb") return {};
  std::vector<NamedCamera> cameras;
  try {
    GltfSceneContents contents = ReadGltfSceneParts(file, AnimationChoice(CliLoadOptions(cli), nullptr));
    for (const GltfCamera& c : contents.cameras) {
      if (!c.perspective) continue;
      std::string name = "camera " + std::to_string(c.index);
      if (!c.name.empty()) name += " \"" + c.name + "\"";
      if (!c.nodeName.empty()) name += " (node \"" + c.nodeName + "\")";
      cameras.push_back(NamedCamera{name, c.desc});
    }
  } catch (const std::exception& e) {  // the scene loaded: its cameras are a convenience
    Warn(file + ": its cameras are not offered: " + e.what());
  }
  return cameras;
}

std::string EnvironmentFolder(const CliOptions& cli) {
  std::string folder = cli.envFolder;
  if (folder.empty()) folder = fs::path(cli.scenePath).parent_path().string();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  if (!cli.envFolder.empty() && !fs::is_directory(folder, ec)) {
    throw AppFailure{kExitBadInput, "--env-dir " + folder + ": not a folder"};
  }
  return fs::absolute(fs::path(folder)).lexically_normal().string();
}

// Ctrl-C: -o and --hdr get the image as it stands (the PNG as the page displays it).
void SaveOnExit(const CliOptions& cli, LiveRender& live) {
  std::string signal = SignalName(StopSignal());
  if (cli.outputPath.empty() && cli.hdrPath.empty()) {
    std::fprintf(stderr, "pathtracer: %s received: the preview stopped; nothing is written (no "
                 "-o or --hdr; the page's Save buttons download the image)\n", signal.c_str());
    return;
  }
  uint32_t spp = 0;
  std::shared_ptr<const FilmImage> image = live.FinalImage(&spp);
  if (!image) {
    std::fprintf(stderr, "pathtracer: %s received: the preview stopped before its first "
                 "sample; nothing is written\n", signal.c_str());
    return;
  }
  DisplaySettings display = live.Display();
  std::string files;
  try {
    if (!cli.outputPath.empty()) {
      // Denoised on the page: the PNG too (as -o --denoise writes it).
      WriteShownImage(cli.outputPath, *image, display);
      files = cli.outputPath;
    }
    if (!cli.hdrPath.empty()) {
      WriteImage(cli.hdrPath, *image, true);
      files += (files.empty() ? "" : " and ") + cli.hdrPath;
    }
  } catch (const ImageError& e) {
    throw AppFailure{kExitRuntimeFailure, e.what()};
  }
  std::fprintf(stderr, "pathtracer: %s received: the preview stopped; wrote %s (%u spp; the "
               "PNG %swith exposure %+g and %s tone mapping)\n", signal.c_str(), files.c_str(),
               spp, image->denoised.empty() ? "" : "denoised, ", double(display.exposure),
               ToneMappingName(display.toneMapping));
}

}  // namespace

int Serve(const CliOptions& cli, const AppBackends& backends) {
  if (!backends.startServer) {
    throw AppFailure{kExitRuntimeFailure,
                     "--serve: this build has no preview server (install libcpp-httplib-dev "
                     "and configure again; see docs/serve.md)"};
  }
  CheckOutputsWritable(cli);
  double loadMs = 0.0, bvhMs = 0.0;
  Scene scene = Build(LoadAndOverride(cli, &loadMs), ChooseBvh(cli, backends), &bvhMs);
  SceneDocument document = LoadDocument(cli, scene.desc);
  BackendKind backend = ChooseBackend(cli.backend, backends);
  LiveSettings settings;
  settings.options = MakeRenderOptions(cli, backend, nullptr);
  settings.display = cli.display;
  settings.cameras = FileCameras(cli, document);
  settings.environmentFolder = EnvironmentFolder(cli);
  SessionFactory factory = backend == BackendKind::kCuda ? backends.cudaSession
                                                         : backends.cpuSession;
  // The page's denoise toggle: the render backend's denoiser, made by the preview.
  DenoiserFactory makeDenoiser = backend == BackendKind::kCuda ? backends.cudaDenoiser
                                                               : backends.cpuDenoiser;
  if (makeDenoiser) {
    int where = backend == BackendKind::kCuda ? settings.options.device : cli.threads;
    // The page's sampler flag changes the variance rule as --sampler does (unless
    // --denoise-variance fixed it).
    DenoiseSettings independent = DenoiseSettingsFor(cli, SamplerKind::kIndependent);
    DenoiseSettings sobol = DenoiseSettingsFor(cli, SamplerKind::kSobol);
    settings.denoiseSettings = [independent, sobol](SamplerKind sampler) {
      return sampler == SamplerKind::kIndependent ? independent : sobol;
    };
    DenoiseSettings first =
        settings.denoiseSettings(cli.sampler.value_or(scene.desc.render.sampler));
    settings.makeDenoiser = [makeDenoiser, where, first] { return makeDenoiser(where, first); };
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
  std::string saves = cli.outputPath.empty() && cli.hdrPath.empty()
                          ? "Ctrl-C stops"
                          : "Ctrl-C stops and writes " +
                                (cli.outputPath.empty() ? cli.hdrPath : cli.outputPath);
  std::fprintf(stderr, "pathtracer: serving %s on http://%s:%d/ (%s)\n", cli.scenePath.c_str(),
               host.c_str(), server->Port(), saves.c_str());
  if (!IsLoopback(config.bind)) {
    Warn("--bind " + config.bind + ": anyone who can reach this address can watch and edit "
         "the render (docs/serve.md shows SSH port forwarding instead)");
  }
  InstallStopSignals(cli.outputPath.empty() && cli.hdrPath.empty()
                         ? "stopping the preview"
                         : "stopping the preview and writing the image");
  while (!StopSignal()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  live.Stop();  // the render first: the page's streams end, the film stays as it is
  server->Stop();
  SaveOnExit(cli, live);
  return kExitOk;
}

}  // namespace pt
