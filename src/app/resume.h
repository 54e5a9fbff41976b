// Resuming a render: the description a resumable --hdr EXR carries (the scene's files by hash,
// and every setting that changes the image), and the check that a --resume file matches the
// render now asked for.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "src/app/cli.h"
#include "src/integrator/render_api.h"

namespace pt {

// The render's identity and the facts a later run reports: the scene file and a hash of it
// and the files it names, image size, crop, seed, spp, depth, roulette, integrator, light
// paths, adaptive sampling, clamp, ray offsets, triangle test, and the film precision.
nlohmann::ordered_json DescribeRender(const CliOptions& cli, const Scene& scene,
                                      const RenderOptions& options, bool adaptive);

// The film to continue, read from cli.resumePath and checked against `current` (this render's
// description, as JSON text). Throws AppFailure with exit status 2 and a message naming the file and every
// difference: another scene (its files changed), size, crop, seed or setting; a film with more
// samples in a pixel than this render's spp; an adaptive render (not resumable yet); a file
// that holds no resumable state.
FilmState LoadResumeFilm(const CliOptions& cli, const std::string& current);

}  // namespace pt
