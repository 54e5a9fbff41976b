# H100, main 662f5eb's binary packed by tools/pack_device.sh; models: ../shared/assets/khronos,
# ../shared/assets/khronos-ext and two Khronos glTF-Sample-Assets fetched outside the repository
# (ToyCar, IridescenceSuzanne; licenses in their folders). One command per model, no options.
python3 tools/contact_sheet.py --binary .device/bin/pathtracer \
  --folder .device/shared/assets/khronos --folder .device/shared/assets/khronos-ext \
  --extra .device/extra/ToyCar/glTF/ToyCar.gltf \
  --extra .device/extra/IridescenceSuzanne/glTF/IridescenceSuzanne.gltf \
  --size 256 --spp 256 --columns 5 --out contact_sheet.png -- --backend cuda
# Order: Box, DamagedHelmet, Duck, TransmissionRoughnessTest, TransmissionTest,
# AnisotropyStrengthTest, ClearCoatTest, NormalTangentMirrorTest, SpecularTest,
# TextureTransformMultiTest, ToyCar, IridescenceSuzanne.
