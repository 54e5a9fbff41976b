# Every model of ../shared/assets/khronos and khronos-ext plus 23 Khronos glTF-Sample-Assets
# models fetched outside the repository into $EXTRA (each model's folder as the sample-assets
# repository has it, licenses included): AnimatedCube AnimatedMorphCube AnimatedTriangle
# BoxAnimated BrainStem CesiumMan CesiumMilkTruck ClearcoatWicker EmissiveStrengthTest Fox
# InterpolationTest IridescenceLamp IridescenceSuzanne MaterialsVariantsShoe RiggedFigure
# RiggedSimple SheenChair SheenCloth SimpleMorph SimpleSkin StainedGlassLamp ToyCar UnlitTest
# (three more fetched incompletely - AnisotropyBarnLamp, BoomBox, IridescenceMetallicSpheres:
# their large files were not in the snapshot - are left out). Main 76365c0's binary, the CPU
# backend on 2 cores (~20 minutes); one command per model, no option but the size and spp.
# Order of the tiles: order.txt. docs/khronos_contact_sheet.png is this sheet.
python3 tools/contact_sheet.py --binary build/pathtracer --folder ../shared/assets/khronos \
  --folder ../shared/assets/khronos-ext --folder "$EXTRA" --size 224 --spp 256 --columns 6 \
  --out contact_sheet.png -- --backend cpu
