"""Builds one of our JSON scenes in Blender Cycles and renders it to a linear EXR, for the
media comparison (benchmarks/media_cycles.py). Run inside Blender:

  blender -b --factory-startup -P benchmarks/media_cycles_blender.py -- SCENE.json OUT.exr SPP
  blender -b --factory-startup -P benchmarks/media_cycles_blender.py -- --to-npy IN.exr OUT.npy

The subset it knows: quads, boxes (with transforms), diffuse and one-sided emissive
materials, homogeneous media in "interface" boxes, grid media from .vdb files in "volume"
objects, a constant background, directional lights (a sun with its angular radius). Our
scenes are Y-up, Blender is Z-up: (x, y, z) -> (x, -z, y). Like-for-like settings
(../shared/toolchain.md): Standard view transform, box filter of width 1, no clamping, no
denoising, Cycles' max_bounces = our max_depth + 1 for every kind of bounce.
"""
import json
import math
import re
import sys

import bpy
import numpy as np


def to_blender(p):
    return (p[0], -p[2], p[1])


def load_json(path):
    text = open(path).read()
    text = re.sub(r"//[^\n]*", "", text)  # our scene files allow // comments
    return json.loads(text)


def trs(t):
    """Our transform: T * Rz * Ry * Rx * S, as a 4x4 numpy matrix (Y-up)."""
    m = np.eye(4)
    if not t:
        return m
    if "matrix" in t:
        return np.array(t["matrix"], dtype=float).reshape(4, 4)
    s = t.get("scale", [1, 1, 1])
    s = [s, s, s] if isinstance(s, (int, float)) else s
    rx, ry, rz = [math.radians(a) for a in t.get("rotate", [0, 0, 0])]
    def rot(axis, a):
        c, n = math.cos(a), math.sin(a)
        r = np.eye(4)
        i, j = [(1, 2), (2, 0), (0, 1)][axis]
        r[i, i], r[i, j], r[j, i], r[j, j] = c, -n, n, c
        return r
    tr = np.eye(4)
    tr[:3, 3] = t.get("translate", [0, 0, 0])
    return tr @ rot(2, rz) @ rot(1, ry) @ rot(0, rx) @ np.diag([s[0], s[1], s[2], 1.0])


def add_mesh(name, verts, faces, material):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([to_blender(v) for v in verts], [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.collection.objects.link(obj)
    obj.data.materials.append(material)
    return obj


def surface_material(name, m):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    if m["type"] == "emissive":
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = (*m["radiance"], 1.0)
        em.inputs["Strength"].default_value = 1.0
        if m.get("two_sided"):
            nt.links.new(em.outputs[0], out.inputs["Surface"])
        else:  # one-sided: the back face is black and emits nothing
            black = nt.nodes.new("ShaderNodeBsdfDiffuse")
            black.inputs["Color"].default_value = (0, 0, 0, 1)
            geo = nt.nodes.new("ShaderNodeNewGeometry")
            mix = nt.nodes.new("ShaderNodeMixShader")
            nt.links.new(geo.outputs["Backfacing"], mix.inputs[0])
            nt.links.new(em.outputs[0], mix.inputs[1])
            nt.links.new(black.outputs[0], mix.inputs[2])
            nt.links.new(mix.outputs[0], out.inputs["Surface"])
    else:
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = (*m["albedo"], 1.0)
        nt.links.new(d.outputs[0], out.inputs["Surface"])
    return mat


def volume_material(name, med, density_attribute=None):
    """sigma_s = density x colour (Volume Scatter), sigma_a = density x (1 - colour) (Volume
    Absorption), times the grid's density attribute for grid media."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    scale = med.get("scale", 1.0)
    sa = [scale * v for v in med["sigma_a"]]
    ss = [scale * v for v in med["sigma_s"]]
    dens = None
    if density_attribute:
        attr = nt.nodes.new("ShaderNodeAttribute")
        attr.attribute_name = density_attribute
        dens = attr.outputs["Fac"]

    def density_input(node, value):
        if dens is None:
            node.inputs["Density"].default_value = value
        else:
            mul = nt.nodes.new("ShaderNodeMath")
            mul.operation = "MULTIPLY"
            mul.inputs[1].default_value = value
            nt.links.new(dens, mul.inputs[0])
            nt.links.new(mul.outputs[0], node.inputs["Density"])

    scatter = nt.nodes.new("ShaderNodeVolumeScatter")
    smax = max(ss) or 1.0
    scatter.inputs["Color"].default_value = (*[v / smax for v in ss], 1.0)
    scatter.inputs["Anisotropy"].default_value = med.get("g", 0.0)
    density_input(scatter, max(ss))
    absorb = nt.nodes.new("ShaderNodeVolumeAbsorption")
    amax = max(sa) or 1.0
    absorb.inputs["Color"].default_value = (*[1.0 - v / amax for v in sa], 1.0)
    density_input(absorb, max(sa))
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(scatter.outputs[0], add.inputs[0])
    nt.links.new(absorb.outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], out.inputs["Volume"])
    mat.cycles.homogeneous_volume = density_attribute is None
    mat.cycles.volume_sampling = "MULTIPLE_IMPORTANCE"
    mat.cycles.volume_interpolation = "LINEAR"
    return mat


def box_quads(lo, hi, m):
    corners = []
    for c in range(8):
        p = [hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2], 1.0]
        corners.append(list((m @ np.array(p))[:3]))
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return corners, faces


def build(scene_path, scene_json):
    s = load_json(scene_path)
    mats = {k: surface_material(k, v) for k, v in s.get("materials", {}).items()}
    media = s.get("media", {})
    for i, o in enumerate(s["objects"]):
        m = trs(o.get("transform"))
        interior = o.get("interior")
        if o["type"] == "quad":
            org, u, v = [np.array(o[k], dtype=float) for k in ("origin", "u", "v")]
            pts = [org, org + u, org + u + v, org + v]
            pts = [list((m @ np.append(p, 1.0))[:3]) for p in pts]
            add_mesh(f"quad{i}", pts, [(0, 1, 2, 3)], mats[o["material"]])
        elif o["type"] == "box":
            verts, faces = box_quads(o["min"], o["max"], m)
            if interior:
                mat = volume_material(f"vol{i}", media[interior])
                if o["material"] != "interface":
                    raise SystemExit("only invisible (interface) medium bounds are supported")
            else:
                mat = mats[o["material"]]
            add_mesh(f"box{i}", verts, faces, mat)
        elif o["type"] == "volume":
            med = media[o["medium"]]
            path = bpy.path.abspath(med["file"]) if med["file"].startswith("/") else \
                scene_path.rsplit("/", 1)[0] + "/" + med["file"]
            bpy.ops.object.volume_import(filepath=path, align="WORLD", location=(0, 0, 0))
            vol = bpy.context.active_object
            vol.rotation_euler = (math.pi / 2, 0, 0)  # our Y-up grid in Blender's Z-up world
            vol.data.materials.append(volume_material(f"grid{i}", med, med.get("grid", "density")))
            if "transform" in med:
                raise SystemExit("grid transforms: bake them into the .vdb (make_vdb --size)")
        else:
            raise SystemExit("unsupported object type " + o["type"])
    if s.get("medium"):
        raise SystemExit("a camera medium: use an interface box instead")
    world = bpy.data.worlds.new("world")
    bpy.context.scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*s.get("background", [0, 0, 0]), 1.0)
    bg.inputs["Strength"].default_value = 1.0
    for i, l in enumerate(s.get("lights", [])):
        if l["type"] != "directional":
            raise SystemExit("unsupported light " + l["type"])
        sun = bpy.data.lights.new(f"sun{i}", "SUN")
        sun.energy = max(l["irradiance"])
        sun.color = tuple(c / sun.energy for c in l["irradiance"])
        sun.angle = 2.0 * math.radians(l.get("angular_radius", 0.0))
        obj = bpy.data.objects.new(f"sun{i}", sun)
        bpy.context.collection.objects.link(obj)
        from mathutils import Vector
        d = Vector(to_blender(l["direction"]))  # the direction light travels
        obj.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()
    cam = s["camera"]
    from mathutils import Vector
    cd = bpy.data.cameras.new("camera")
    cd.sensor_fit = "VERTICAL"
    cd.angle_y = math.radians(cam["fov_y"])
    co = bpy.data.objects.new("camera", cd)
    bpy.context.collection.objects.link(co)
    co.location = Vector(to_blender(cam["position"]))
    look = Vector(to_blender(cam["look_at"])) - co.location
    co.rotation_euler = look.to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.camera = co
    return s


def settings(s, out, spp):
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.samples = spp
    sc.cycles.use_adaptive_sampling = False
    sc.cycles.use_denoising = False
    sc.cycles.seed = 1
    depth = s["render"]["max_depth"] + 1
    for k in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
              "volume_bounces"):
        setattr(sc.cycles, k, depth)
    sc.cycles.transparent_max_bounces = 64
    sc.cycles.sample_clamp_direct = 0.0
    sc.cycles.sample_clamp_indirect = 0.0
    sc.cycles.caustics_reflective = True
    sc.cycles.caustics_refractive = True
    sc.cycles.blur_glossy = 0.0
    sc.cycles.pixel_filter_type = "BOX"
    sc.cycles.filter_width = 1.0
    sc.cycles.volume_step_rate = 0.25
    sc.cycles.volume_max_steps = 4096
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    sc.render.film_transparent = False
    sc.render.resolution_x = s["render"]["width"]
    sc.render.resolution_y = s["render"]["height"]
    sc.render.resolution_percentage = 100
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.color_mode = "RGB"
    sc.render.filepath = out


def to_npy(exr, out):
    img = bpy.data.images.load(exr)
    w, h = img.size
    px = np.array(img.pixels[:], dtype=np.float32).reshape(h, w, img.channels)[::-1, :, :3]
    np.save(out, px)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    if argv[0] == "--to-npy":
        to_npy(argv[1], argv[2])
        return
    scene_path, out, spp = argv[0], argv[1], int(argv[2])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    s = build(scene_path, None)
    settings(s, out, spp)
    bpy.ops.render.render(write_still=True)


main()
