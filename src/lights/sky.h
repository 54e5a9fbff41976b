// An analytic daylight sky that needs no image file: the Preetham, Shirley and Smits (1999)
// model of the clear sky's luminance and chromaticity (Perez et al.'s five-parameter function
// of turbidity and sun position), its sun with Preetham's attenuation by Rayleigh and aerosol
// scattering at three wavelengths, and a ground of constant radiance below the horizon.
//
// Units: the sky's luminance Y (cd/m^2) becomes radiance Y / 683 (683 lm per watt at 555 nm);
// the sun's irradiance is the solar illuminance outside the atmosphere (128 klx) times the
// attenuation, over 683 too, so sun and sky keep their physical ratio (about 100 klx of sun to
// 15-25 klx of sky at midday). `strength` scales both.
//
// The sky is baked into an equirectangular map (the environment convention of
// src/scene/scene_types.h) at scene load, and `make_sky` writes it to an EXR file.
#pragma once

#include <vector>

#include "src/scene/scene.h"

namespace pt {

// The sun's angular radius seen from the Earth: 0.2666 degrees.
constexpr double kSunAngularRadius = 0.004653;

// Towards the sun in the map's frame: elevation above the horizon, azimuth from -Z towards +X
// (the map's centre column is azimuth 0), both in degrees.
vec3 SunDirection(double elevationDegrees, double azimuthDegrees);

// Linear RGB radiance of the sky (without the sun) along unit direction w of the map's frame;
// only meaningful above the horizon (w.y > 0).
vec3 SkyRadiance(const SkyDesc& sky, vec3 w);

// Irradiance of the sun on a plane facing it (linear RGB); zero below the horizon.
vec3 SunIrradiance(const SkyDesc& sky);

// The sky as an equirectangular map of sky.width x sky.width / 2 texels (each texel the mean
// of 2 x 2 samples), the ground below the horizon at albedo x (sky + sun irradiance on the
// horizontal plane) / pi. With sunInMap the sun's disk is added to the texels it covers, each
// by the share of its solid angle inside the disk, so the map holds the sun's whole power.
void BakeSky(const SkyDesc& sky, bool sunInMap, uint32_t* width, uint32_t* height,
             std::vector<vec3>* texels);

// The sun of the sky as a directional light (part of the environment: it turns with
// `rotate` and scales with `strength`).
DirectionalLightDesc SkySun(const SkyDesc& sky);

}  // namespace pt
