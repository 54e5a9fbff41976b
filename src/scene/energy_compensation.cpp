#include "src/scene/energy_compensation.h"

namespace pt {

void EnableEnergyCompensation(SceneDesc* scene) {
  for (Material& m : scene->materials)
    if (m.type == MaterialType::kConductor || m.type == MaterialType::kGltfPbr)
      m.flags |= kMaterialEnergyCompensation;
}

}  // namespace pt
