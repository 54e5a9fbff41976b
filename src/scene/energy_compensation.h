// --energy-compensation on: marks every metal (conductor, glTF) so that its rough GGX lobe
// gains back the energy single scattering loses (src/materials/gltf_layered.h; scenes with
// such metals run the layered shade variant).
#pragma once

#include "src/scene/scene.h"

namespace pt {

void EnableEnergyCompensation(SceneDesc* scene);

}  // namespace pt
