"""A dict scene is the same scene as its JSON file; edits (camera, material, instance transform)
render what a fresh load of the edited scene renders; the BVH is kept between renders and
rebuilt only when an option needs it."""
import numpy as np
import pytest

import pathtracer
from conftest import SCENES, SMALL, assert_identical, scene_dict


def instanced_dict():
    scene = scene_dict(SCENES / "instanced_shapes.json")
    for mesh in scene["meshes"].values():
        mesh["file"] = str(SCENES / mesh["file"])
    return scene


def render(scene, **options):
    return pathtracer.render(scene, **dict(SMALL, **options)).image


def test_dict_scene_equals_its_file(cornell):
    as_dict = pathtracer.Scene(scene_dict(SCENES / "cornell_box.json"))
    assert_identical(render(as_dict), render(cornell))
    # Relative mesh paths of a dict resolve against base_dir.
    instanced = pathtracer.Scene(scene_dict(SCENES / "instanced_shapes.json"), base_dir=SCENES)
    assert_identical(render(instanced), render(pathtracer.Scene(SCENES / "instanced_shapes.json")))


def test_camera_edit_equals_a_fresh_load(cornell):
    before = render(cornell)
    cornell.set_camera(position=[0.3, 1.1, 3.5], fov_y=45)
    edited = scene_dict(SCENES / "cornell_box.json")
    edited["camera"].update(position=[0.3, 1.1, 3.5], fov_y=45)
    after = render(cornell)
    assert_identical(after, render(pathtracer.Scene(edited)))
    assert not np.array_equal(after, before)
    assert cornell.camera["position"] == pytest.approx([0.3, 1.1, 3.5])


def test_material_edit_equals_a_fresh_load_and_keeps_the_bvh(cornell):
    first = pathtracer.render(cornell, **SMALL)
    assert first.stats["time_ms"]["bvh_build"] == 0.0  # built at load, kept
    cornell.set_material("red", albedo=[0.1, 0.2, 0.7])
    cornell.set_material("lamp", radiance=[30, 30, 30])
    edited = scene_dict(SCENES / "cornell_box.json")
    edited["materials"]["red"]["albedo"] = [0.1, 0.2, 0.7]
    edited["materials"]["lamp"]["radiance"] = [30, 30, 30]
    result = pathtracer.render(cornell, **SMALL)
    assert result.stats["time_ms"]["bvh_build"] == 0.0
    assert_identical(result.image, render(pathtracer.Scene(edited)))
    assert cornell.material("red") == {"type": "diffuse", "albedo": [0.1, 0.2, 0.7]}
    # A new type replaces the material whole.
    cornell.set_material("red", type="conductor", albedo=[0.9, 0.9, 0.9], roughness=0.3)
    edited["materials"]["red"] = {"type": "conductor", "albedo": [0.9, 0.9, 0.9], "roughness": 0.3}
    assert_identical(render(cornell), render(pathtracer.Scene(edited)))


def test_instance_transform_edit_equals_a_fresh_load():
    scene = pathtracer.Scene(instanced_dict())
    assert scene.instance_count == 5
    moved = {"rotate": [0, 80, 0], "scale": [0.5, 0.5, 0.5], "translate": [0.2, 0.3, 0.1]}
    matrix = np.array([[0.8, 0, 0, 0.5], [0, 0.8, 0, 0.2], [0, 0, 0.8, -0.3], [0, 0, 0, 1]])
    scene.set_instance_transform(0, moved)
    scene.set_instance_transform(3, matrix)
    edited = instanced_dict()
    edited["objects"][3]["transform"] = moved  # instance 0 is the file's fourth object
    edited["objects"][6]["transform"] = {"matrix": matrix.ravel().tolist()}
    result = pathtracer.render(scene, **SMALL)
    assert result.stats["time_ms"]["bvh_build"] == 0.0  # only the top level was rebuilt
    assert_identical(result.image, render(pathtracer.Scene(edited)))
    np.testing.assert_allclose(scene.instance_transform(3), matrix, rtol=1e-7)
    assert '"matrix"' in scene.to_json()


def test_options_rebuild_only_what_they_change(cornell):
    assert pathtracer.render(cornell, **SMALL).stats["bvh"]["layout"] == "wide"
    binary = pathtracer.render(cornell, bvh="binary", **SMALL)
    assert binary.stats["bvh"]["layout"] == "binary" and binary.stats["time_ms"]["bvh_build"] > 0
    again = pathtracer.render(cornell, **dict(SMALL, bvh="binary", max_depth=2))
    assert again.stats["time_ms"]["bvh_build"] == 0.0


def test_model_file_camera_edit():
    scene = pathtracer.Scene(SCENES / "meshes" / "smooth_shapes.glb")
    before = render(scene)
    framed = scene.camera  # the automatic camera, as framed for this render's aspect
    scene.set_camera(fov_y=framed["fov_y"] / 2)
    assert scene.camera["position"] == framed["position"]
    assert not np.array_equal(render(scene), before)
