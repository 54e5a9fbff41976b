"""Blender (3.4) side of the comparison: imports a glTF model with Blender's own importer and
renders it with Cycles in the like-for-like settings of ../shared/toolchain.md (numpy alias fix,
Standard view transform, box filter, no clamping, no denoising, opaque film, linear EXR),
through the camera of our JSON scene, under a uniform white world of strength 1.

  blender -b -P cycles_render.py -- SCENE.json OUT.exr SPP

Cycles' max_bounces N equals our max_depth N + 1, so max_bounces = render.max_depth - 1."""
import json
import math
import sys

import numpy as np

np.bool = bool  # Debian 12's numpy removed the aliases the bundled importer uses
np.int = int
np.float = float
np.object = object

import bpy  # noqa: E402
import mathutils  # noqa: E402


def main():
    scene_path, out, spp = sys.argv[sys.argv.index('--') + 1:][:3]
    desc = json.load(open(scene_path))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    mesh = desc['objects'][0]
    bpy.ops.import_scene.gltf(filepath=mesh['file'])
    scene = bpy.context.scene
    cam_desc = desc['camera']
    cam_data = bpy.data.cameras.new('cam')
    cam_data.sensor_fit = 'VERTICAL'
    cam_data.angle_y = math.radians(cam_desc['fov_y'])
    cam = bpy.data.objects.new('cam', cam_data)
    scene.collection.objects.link(cam)
    pos = mathutils.Vector(cam_desc['position'])
    target = mathutils.Vector(cam_desc['look_at'])
    # glTF's +Y up is Blender's +Z up: the importer maps (x, y, z) to (x, -z, y).
    to_blender = lambda v: mathutils.Vector((v.x, -v.z, v.y))
    pos, target = to_blender(pos), to_blender(target)
    cam.location = pos
    cam.rotation_euler = (target - pos).to_track_quat('-Z', 'Y').to_euler()
    scene.camera = cam
    world = bpy.data.worlds.new('white')
    world.use_nodes = True
    bg = world.node_tree.nodes['Background']
    bg.inputs['Color'].default_value = (1.0, 1.0, 1.0, 1.0)
    bg.inputs['Strength'].default_value = 1.0
    scene.world = world
    r = desc['render']
    scene.render.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = int(spp)
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.seed = 1
    bounces = max(r['max_depth'] - 1, 0)
    for attr in ('max_bounces', 'diffuse_bounces', 'glossy_bounces', 'transmission_bounces',
                 'volume_bounces', 'transparent_max_bounces'):
        setattr(scene.cycles, attr, bounces if attr != 'transparent_max_bounces' else 64)
    scene.cycles.sample_clamp_direct = 0.0
    scene.cycles.sample_clamp_indirect = 0.0
    scene.cycles.pixel_filter_type = 'BOX'
    scene.cycles.filter_width = 1.0
    scene.render.film_transparent = False
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.resolution_x = r['width']
    scene.render.resolution_y = r['height']
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = 'OPEN_EXR'
    scene.render.image_settings.color_depth = '32'
    scene.render.image_settings.color_mode = 'RGB'
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)


main()
