"""Renders a glTF model in Blender Cycles like the path tracer renders a JSON scene that
includes it: the same camera (glTF coordinates, converted to Blender's Z-up), a uniform white
world of the given radiance, box pixel filter of width 1, no denoising, Standard view
transform, linear float output. Writes the image as a .npy of shape (height, width, 3), rows
top to bottom (what benchmarks/cycles/compare.py reads).

    blender -b -P benchmarks/cycles/render_cycles.py -- MODEL.glb OUT.npy \
        --position X Y Z --look-at X Y Z --fov-y DEG --width W --height H --spp N \
        [--max-bounces B] [--background R]

Cycles' max_bounces B matches the path tracer's max_depth B + 1 (docs: toolchain notes).
"""
import argparse
import math
import os
import sys
import tempfile

import numpy as np

# Debian 12's numpy dropped aliases Blender 3.4's glTF importer still uses.
np.bool = bool
np.int = int
np.float = float
np.object = object

import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("out")
    ap.add_argument("--position", type=float, nargs=3, required=True)
    ap.add_argument("--look-at", type=float, nargs=3, required=True)
    ap.add_argument("--fov-y", type=float, required=True)
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--height", type=int, default=256)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--max-bounces", type=int, default=7)
    ap.add_argument("--background", type=float, default=1.0)
    return ap.parse_args(argv)


def to_blender(p):
    """glTF (+Y up) to Blender (+Z up), as the importer converts: (x, y, z) -> (x, -z, y)."""
    return Vector((p[0], -p[2], p[1]))


def main():
    a = parse()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=os.path.abspath(a.model))
    scene = bpy.context.scene
    cam_data = bpy.data.cameras.new("cam")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(a.fov_y)
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    cam.location = to_blender(a.position)
    direction = to_blender(a.look_at) - cam.location
    cam.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    world = bpy.data.worlds.new("white")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs[0].default_value = (a.background, a.background, a.background, 1.0)
    bg.inputs[1].default_value = 1.0
    scene.world = world
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = a.spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = a.max_bounces
    c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = a.max_bounces
    c.transparent_max_bounces = a.max_bounces
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.resolution_x = a.width
    scene.render.resolution_y = a.height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    exr = os.path.join(tempfile.mkdtemp(), "cycles.exr")
    scene.render.filepath = exr
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(exr)
    px = np.array(img.pixels[:], dtype=np.float32).reshape(a.height, a.width, 4)[::-1, :, :3]
    np.save(a.out, px)
    print("wrote", a.out)


main()
