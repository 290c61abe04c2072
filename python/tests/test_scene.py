"""Loading scenes of every dialect, their info, and errors with file, line, column."""

import json
import subprocess
import sys

import pytest

import prism
from conftest import SCENES

OBJ = """# a unit quad and a triangle
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
f 1 2 3 4
f 1 2 5
"""


@pytest.fixture
def obj_file(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text(OBJ)
    return path


def test_every_dialect_loads_with_its_info(obj_file):
    objx = prism.load_scene(SCENES / "example" / "example.objx")
    toml = prism.load_scene(SCENES / "showcase" / "showcase.toml")
    obj = prism.load_scene(obj_file)
    assert [s.dialect for s in (objx, toml, obj)] == ["objx", "toml", "obj"]
    info = objx.info()
    assert (info["spheres"], info["rectangles"], info["light_kinds"]) == (2, 3, ["point"])
    assert obj.info()["triangles"] == 3 and obj.info()["vertices"] == 5
    assert toml.info()["lights"] >= 1
    assert "example.objx" in repr(objx)


def test_dialect_overrides_the_extension(tmp_path):
    path = tmp_path / "quad.txt"
    path.write_text(OBJ)
    assert prism.load_scene(path, dialect="obj").info()["triangles"] == 3
    with pytest.raises(ValueError, match="unknown dialect"):
        prism.load_scene(path, dialect="stl")


def test_info_is_prism_info_json(prism_bin):
    scene = SCENES / "showcase" / "showcase.toml"
    out = subprocess.run([str(prism_bin), "info", "--json", str(scene)],
                         check=True, capture_output=True, text=True).stdout
    assert prism.load_scene(scene).info() == json.loads(out)


def test_scene_shows_itself_in_notebooks():
    html = prism.load_scene(SCENES / "example" / "example.objx")._repr_html_()
    assert html.startswith("<table>") and "objx" in html and "point" in html


def test_a_parse_error_names_file_and_line(tmp_path):
    path = tmp_path / "bad.objx"
    path.write_text("v 0 0 0\nv 1 0 0\nf 0 -2\n")
    with pytest.raises(prism.SceneError) as caught:
        prism.load_scene(path)
    err = caught.value
    assert isinstance(err, ValueError) and isinstance(err, prism.PrismError)
    assert (err.file, err.line, err.column) == (str(path), 3, None)
    assert str(err).startswith(f"{path}:3:")


def test_a_toml_error_names_line_and_column(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[render]\nwidth = 64\n  colour = 3\n')
    with pytest.raises(prism.SceneError) as caught:
        prism.load_scene(path)
    err = caught.value
    assert (err.file, err.line, err.column) == (str(path), 3, 3)


def test_a_missing_file_is_a_file_error(tmp_path):
    with pytest.raises(prism.FileError) as caught:
        prism.load_scene(tmp_path / "none.objx")
    assert isinstance(caught.value, OSError)
    assert caught.value.file == str(tmp_path / "none.objx")


def test_restricted_reads_refuse_files_outside_the_folder(tmp_path):
    # A process of its own: the restriction lasts for the rest of the process.
    jail = tmp_path / "jail"
    jail.mkdir()
    (tmp_path / "outside.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (jail / "inside.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    script = f"""
import prism
prism.restrict_paths({str(jail)!r})
prism.load_scene({str(jail / "inside.obj")!r})
try:
    prism.load_scene({str(tmp_path / "outside.obj")!r})
except prism.PrismError as e:
    assert "restricted to" in str(e), e
    print("refused")
try:
    prism.restrict_paths({str(tmp_path)!r})
except prism.SettingsError as e:
    print("fixed")
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["refused", "fixed"]


BLENDER = SCENES / "blender" / "blender-export.glb"


def test_a_gltf_scene_loads_with_its_cameras_and_renders_with_them():
    scene = prism.load_scene(BLENDER)
    assert scene.dialect == "gltf"
    info = scene.info()
    assert info["light_kinds"] == ["point", "directional"]
    assert [c["name"] for c in info["cameras"]] == ["Camera"]
    image = prism.render(scene, width=40, aa=1, camera_index=0)
    assert image.shape == (25, 40, 3)
    with pytest.raises(prism.SettingsError, match="no camera is named `Top`"):
        prism.render(scene, width=40, camera_name="Top")


def quad_dict(mesh):
    return {
        "camera": {"from": [0.5, 0.5, 3], "at": [0.5, 0.5, 0], "fov": 40},
        "render": {"width": 32, "height": 24, "aa": 1},
        "material": [{"name": "red", "color": [0.8, 0.1, 0.1]}],
        "object": [dict(mesh, type="mesh", material="red"),
                   {"type": "sphere", "center": [0, 0, -3], "radius": 1}],
        "light": [{"type": "point", "position": [2, 2, 2]}],
    }


def test_a_scene_from_a_dict_with_arrays_equals_the_same_scene_from_files(tmp_path):
    np = pytest.importorskip("numpy")
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float64)
    faces = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float32)
    from_arrays = prism.scene_from_dict(
        quad_dict({"vertices": vertices, "faces": faces, "normals": normals, "uvs": uvs}))
    (tmp_path / "quad.obj").write_text(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
    from_files = prism.scene_from_dict(quad_dict({"file": "quad.obj"}), folder=tmp_path)
    a, b = prism.render(from_arrays), prism.render(from_files)
    assert a.shape == (24, 32, 3) and a.max() > 0.1
    assert a.tobytes() == b.tobytes()
    assert (from_arrays.info()["triangles"], from_arrays.info()["spheres"]) == (2, 1)


def test_vertex_colours_multiply_the_albedo_as_a_ply_file_s_do(tmp_path):
    np = pytest.importorskip("numpy")
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float32)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    colors = np.array([[1, 0, 0, 1], [1, 0, 0, 1], [0, 0, 1, 1], [0, 0, 1, 1]], dtype=np.float32)
    quad = {"vertices": vertices, "faces": faces, "colors": colors}
    painted = prism.render(prism.scene_from_dict(quad_dict(quad)))
    (tmp_path / "quad.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 255 0 0\n1 0 0 255 0 0\n1 1 0 0 0 255\n0 1 0 0 0 255\n3 0 1 2\n3 0 2 3\n")
    from_file = prism.render(prism.scene_from_dict(quad_dict({"file": "quad.ply"}), folder=tmp_path))
    assert painted.tobytes() == from_file.tobytes()
    plain = prism.render(prism.scene_from_dict(quad_dict({"vertices": vertices, "faces": faces})))
    assert painted[12, 16, 1] < plain[12, 16, 1]  # the green of the red paint is gone
    with pytest.raises(ValueError, match="colors must be N x 3 or N x 4"):
        prism.scene_from_dict(quad_dict(dict(quad, colors=colors[:2])))
    with pytest.raises(prism.SceneError, match="colour 0 is not a finite, non-negative"):
        prism.scene_from_dict(quad_dict(dict(quad, colors=-colors)))


def test_scene_dict_errors_name_the_entry():
    with pytest.raises(prism.SceneError, match=r"object\[0\]: `radius = -1`: expected radius > 0"):
        prism.scene_from_dict({"object": [{"type": "sphere", "radius": -1}]})
    with pytest.raises(ValueError, match="faces must be M x 3"):
        prism.scene_from_dict({"object": [{"type": "mesh", "vertices": [[0, 0, 0]], "faces": [0, 0, 0]}]})
    with pytest.raises(prism.SceneError, match="face 0 names vertex 5, past the 3 vertices"):
        prism.scene_from_dict({"object": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                                           "faces": [[0, 1, 5]]}]})


def test_instances_place_a_mesh_by_an_n_by_4_by_4_array_of_transforms():
    np = pytest.importorskip("numpy")
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float64)
    faces = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)
    moves = [(-2.5, 0.0), (-1.0, -0.5), (0.5, 0.25), (1.5, -1.0)]
    transforms = np.tile(np.eye(4), (len(moves), 1, 1))
    for k, (x, y) in enumerate(moves):
        transforms[k, 0, 3], transforms[k, 1, 3] = x, y

    def scene(objects):
        return prism.scene_from_dict({
            "camera": {"from": [0, 0, 6], "at": [0, 0, 0], "fov": 50},
            "render": {"width": 48, "height": 32, "aa": 1},
            "material": [{"name": "red", "color": [0.8, 0.1, 0.1]}],
            "object": objects,
            "light": [{"type": "point", "position": [2, 2, 4]}],
        })

    quad = {"name": "quad", "type": "mesh", "vertices": vertices, "faces": faces,
            "material": "red", "translate": [0, 0, -50]}
    placed = scene([quad, {"type": "instance", "of": "quad", "transforms": transforms}])
    info = placed.info()
    assert (info["instances"], info["instanced_objects"]) == (4, 1)
    assert (info["triangles"], info["unique_triangles"]) == (2 + 8, 4)
    copies = scene([quad] + [dict(quad, name=f"q{k}", translate=[x, y, 0])
                             for k, (x, y) in enumerate(moves)])
    a, b = prism.render(placed), prism.render(copies)
    assert a.max() > 0.1
    # The same picture: instances round their transform to floats, copies place in
    # doubles, so an edge pixel may differ by a hair.
    assert np.abs(a - b).mean() < 1e-3
    # The array goes over as bytes: the same scene as the matrices written out.
    listed = scene([quad, {"type": "instance", "of": "quad", "transforms": transforms.tolist()}])
    assert prism.render(listed).tobytes() == a.tobytes()
    # Scaled to nothing along its normal (Blender allows a scale of 0 on one axis), the
    # quad is as it was: copied into the scene, where an instance has no inverse.
    flat = transforms.copy()
    flat[:, 2, 2] = 0.0
    flattened = scene([quad, {"type": "instance", "of": "quad", "transforms": flat}])
    assert (flattened.info()["instances"], flattened.info()["triangles"]) == (0, 2 + 8)
    assert np.abs(prism.render(flattened) - a).mean() < 1e-3
    bad = transforms.copy()
    bad[2, 3, 0] = 1.0
    with pytest.raises(prism.SceneError, match="last row of transform 2"):
        scene([quad, {"type": "instance", "of": "quad", "transforms": bad}])
    bad[2, 3, 0], bad[1, 0, 0] = 0.0, np.nan
    with pytest.raises(prism.SceneError, match="finite numbers in transform 1"):
        scene([quad, {"type": "instance", "of": "quad", "transforms": bad}])
    with pytest.raises(ValueError, match="transforms must be N x 4 x 4"):
        scene([quad, {"type": "instance", "of": "quad", "transforms": transforms[:, :3]}])
    with pytest.raises(prism.SceneError, match="which no array handed over holds"):
        scene([quad, {"type": "instance", "of": "quad", "transforms": "elsewhere"}])
