#include "src/app/outputs.h"

#include "src/app/app_failure.h"
#include "src/app/run.h"
#include "src/io/film_state_exr.h"
#include "src/io/image_io.h"

namespace pt {

void CheckOutputsWritable(const CliOptions& cli) {
  for (const std::string* path :
       {&cli.outputPath, &cli.hdrPath, &cli.statsJsonPath, &cli.sppMapPath}) {
    std::string why;
    if (!path->empty() && !CheckWritable(*path, &why)) {
      throw AppFailure{kExitRuntimeFailure, "cannot write " + *path + ": " + why};
    }
  }
}

void WriteCheckpoint(const CliOptions& cli, const FilmImage& image, const ResumableState& state) {
  WriteResumableExr(cli.hdrPath, image, *state.film, state.doubleFilm, state.description);
}

std::vector<std::string> WriteImages(const CliOptions& cli, const FilmImage& image,
                                     const ResumableState* state) {
  std::vector<std::string> written;
  if (!image.denoised.empty()) {  // --denoise: -o shows the denoised image
    FilmImage shown;
    shown.width = image.width;
    shown.height = image.height;
    shown.rgb = image.denoised;
    WriteImage(cli.outputPath, shown, false);
  } else {
    WriteImage(cli.outputPath, image, false);
  }
  written.push_back(cli.outputPath);
  if (!cli.hdrPath.empty()) {
    if (state && IsExrPath(cli.hdrPath)) WriteCheckpoint(cli, image, *state);
    else WriteImage(cli.hdrPath, image, true);
    written.push_back(cli.hdrPath);
  }
  if (!cli.sppMapPath.empty()) {
    WriteSppMap(cli.sppMapPath, image);
    written.push_back(cli.sppMapPath);
  }
  return written;
}

}  // namespace pt
