"""Bad input raises a Python exception with the command line's message (the file and the field),
never ends the interpreter; a refused edit leaves the scene as it was."""
import json

import numpy as np
import pytest

import pathtracer
from conftest import SCENES, SMALL, assert_identical, cli_error, scene_dict


def bad_cornell(tmp_path, edit):
    scene = scene_dict(SCENES / "cornell_box.json")
    edit(scene)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(scene))
    return scene, path


@pytest.mark.parametrize("edit", [
    lambda s: s["materials"]["red"].update(albedo=[0.63, 1.3, 0.05]),
    lambda s: s["objects"][0].update(material="purple"),
    lambda s: s["camera"].update(fov_y=190),
    lambda s: s["render"].update(spp=0),
    lambda s: s["objects"].append({"type": "sphere", "center": [0, 1, 0], "radius": -1,
                                   "material": "white"}),
    lambda s: s.update(lights=[{"type": "spot", "position": [0, 1, 0]}]),
])
def test_bad_scene_raises_the_cli_message(tmp_path, edit):
    scene, path = bad_cornell(tmp_path, edit)
    status, message = cli_error([path, "-o", tmp_path / "x.png"])
    assert status == 2 and message.startswith(str(path) + ": ")
    with pytest.raises(ValueError) as file_error:
        pathtracer.Scene(path)
    assert str(file_error.value) == message
    with pytest.raises(ValueError) as dict_error:
        pathtracer.Scene(scene)  # the same message, naming "<dict>"
    assert str(dict_error.value) == message.replace(str(path), "<dict>", 1)
    assert not (tmp_path / "x.png").exists()


def test_missing_file_names_it(tmp_path):
    with pytest.raises(ValueError, match=r"nope\.json: cannot open the scene file"):
        pathtracer.Scene(tmp_path / "nope.json")
    with pytest.raises(ValueError, match=r"nope\.glb"):
        pathtracer.Scene(tmp_path / "nope.glb")
    with pytest.raises(TypeError):
        pathtracer.Scene(42)


@pytest.mark.parametrize("options, flags", [
    (dict(sort="sideways"), ["--sort", "sideways"]),
    (dict(max_depth=-1), ["--max-depth", "-1"]),
    (dict(spp=0), ["--spp", "0"]),
    (dict(width=100000), ["--width", "100000"]),
    (dict(crop=(0, 0, 50, 10)), ["--crop", "0,0,50,10"]),
    (dict(integrator="path"), ["--integrator", "path"]),
    (dict(sampler="halton"), ["--sampler", "halton"]),
    (dict(env="/no/such/map.hdr"), ["--env", "/no/such/map.hdr"]),
    (dict(chunks=9, spp=4, adaptive="off"), ["--chunks", "9", "--spp", "4", "--adaptive", "off"]),
])
def test_bad_option_raises_the_cli_message(tmp_path, cornell, options, flags):
    status, message = cli_error([SCENES / "cornell_box.json", "-o", tmp_path / "x.png",
                                 "--width", "24", "--height", "20", *flags])
    assert status in (1, 2) and message
    with pytest.raises(ValueError) as error:
        pathtracer.render(cornell, **dict(dict(width=24, height=20), **options))
    assert str(error.value) == message


def test_unknown_or_refused_keywords_are_type_errors(cornell):
    with pytest.raises(TypeError, match="unknown option 'max_dpeth'"):
        pathtracer.render(cornell, max_dpeth=3)
    with pytest.raises(TypeError, match="result.save"):
        pathtracer.render(cornell, hdr="x.exr")
    with pytest.raises(TypeError, match="pathtracer.Scene"):
        pathtracer.render(cornell, camera="1")


def test_missing_backend_is_a_runtime_error(cornell):
    if pathtracer.cuda_available():
        pytest.skip("a GPU is here")
    with pytest.raises(RuntimeError, match="--backend cuda: "):
        pathtracer.render(cornell, **dict(SMALL, backend="cuda"))


def test_refused_edits_leave_the_scene_unchanged(cornell):
    before = pathtracer.render(cornell, **SMALL).image
    with pytest.raises(ValueError, match=r"cornell_box\.json: camera\.fov_y: 200 is outside"):
        cornell.set_camera(fov_y=200)
    with pytest.raises(ValueError, match=r"albedo\[0\]: 2 is outside \[0, 1\]"):
        cornell.set_material("red", albedo=[2, 0, 0])
    with pytest.raises(ValueError, match='no material "blue" \\(the scene has: white, red'):
        cornell.set_material("blue", albedo=[0, 0, 1])
    with pytest.raises(ValueError, match="no instance 0"):
        cornell.set_instance_transform(0, np.eye(4))
    assert_identical(pathtracer.render(cornell, **SMALL).image, before)
    instanced = pathtracer.Scene(SCENES / "instanced_shapes.json")
    with pytest.raises(ValueError, match=r"objects\[3\]\.transform"):
        instanced.set_instance_transform(0, np.zeros((4, 4)))


def test_unknown_gltf_camera_raises_the_cli_message(tmp_path):
    model = SCENES / "meshes" / "smooth_shapes.glb"
    status, message = cli_error([model, "-o", tmp_path / "x.png", "--camera", "Main"])
    assert status == 2 and "--camera" in message
    with pytest.raises(ValueError) as error:
        pathtracer.Scene(model, camera="Main")
    assert str(error.value) == message
