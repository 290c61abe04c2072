"""A Blender depsgraph as a Prism scene: one converter for F12 and the viewport.

Every mesh the depsgraph evaluates is read once, however many times it is placed
(collection instances, particles, geometry nodes, linked duplicates), and placed by
each of its instances' matrices: a scene of instances holds the mesh once in Prism
too. Objects, lights, the camera and the world come from the depsgraph as it
evaluated them, so modifiers, drivers and animation are what Blender shows.
"""

import bpy
import numpy as np

from . import camera as cameras
from . import lights as light_export
from . import materials as material_export
from . import world as world_export
from .meshes import mesh_parts

#: Object types whose evaluated geometry is a mesh.
GEOMETRY = {"MESH", "CURVE", "SURFACE", "META", "FONT"}
#: The name of the grey every slot without a material wears.
DEFAULT_MATERIAL = "prism-default"


class Export:
    """What the converter made: the scene (as `prism.scene_from_dict` takes it), the
    warnings, and counts for the log and tests."""

    def __init__(self, scene, warnings, meshes, placements, triangles):
        self.scene = scene
        self.warnings = warnings
        self.meshes = meshes
        self.placements = placements
        self.triangles = triangles


class MeshCache:
    """Meshes read earlier, by the name of their source object and data: the viewport
    keeps one between updates and drops what an update changes."""

    def __init__(self):
        self._parts = {}

    def get(self, key):
        return self._parts.get(key)

    def put(self, key, parts):
        self._parts[key] = parts

    def discard(self, names):
        """Forget every mesh read from an object or mesh named in `names`."""
        for key in [k for k in self._parts if k[0] in names or k[1] in names]:
            del self._parts[key]

    def clear(self):
        self._parts.clear()


def _rows(matrix):
    return np.asarray([list(row) for row in matrix], dtype=np.float64)


def _mesh_key(obj, is_instance):
    """Which placements share a mesh: the same source object and data. Geometry a node
    tree made (no source object of its own) is told apart by its data block."""
    original = obj.original
    data = obj.data
    data_name = data.original.name if data is not None and data.original is not None else ""
    if is_instance and data is not None and original.data is not None and \
            data.original is not original.data:
        return (f"{original.name}", f"{data_name}#{data.as_pointer():x}")
    return (original.name, data_name)


def _slot_materials(obj):
    return tuple(slot.material for slot in obj.material_slots)


def _names(materials):
    return tuple(m.name if m is not None else None for m in materials)


def export(depsgraph, width, height, camera_object=None, view=None, settings=None,
           cache=None, images=None):
    """The Prism scene of `depsgraph` for a `width` x `height` image, seen from
    `camera_object` (an evaluated camera) or `view` (a `[camera]` table, the viewport's).
    `settings` is the `[render]` table; `cache` a `MeshCache` to reuse meshes from."""
    warnings = []
    seen = set()

    def warn(text):
        if text not in seen:
            seen.add(text)
            warnings.append(text)

    cache = cache if cache is not None else MeshCache()
    images = images if images is not None else material_export.Images()
    meshes = {}  # key -> (parts, slot materials)
    placements = {}  # key -> [matrix rows]
    materials = {}  # name -> scene-file material
    vertex_colors = {}  # material name -> the colour attribute it reads
    lights = []

    def material_name(material):
        """The name a slot's material goes by, converted the first time it is met."""
        name = material.name if material is not None else DEFAULT_MATERIAL
        if name not in materials:
            params = material_export.material_dict(material, images, warn)
            reads = params.pop(material_export.VERTEX_COLORS, None)
            materials[name] = params
            if reads is not None:
                vertex_colors[name] = reads
        return name

    for inst in depsgraph.object_instances:
        obj = inst.object
        if obj.type in GEOMETRY:
            slots = _slot_materials(obj)
            key = _mesh_key(obj, inst.is_instance) + (_names(slots),)
            if key not in meshes:
                names = [material_name(m) for m in slots]
                wanted = [vertex_colors[n] for n in names if n in vertex_colors]
                attribute = wanted[0] if wanted else None
                if len(set(wanted)) > 1:
                    warn(f"object {obj.name}: its materials read different colour attributes; "
                         f"\"{attribute}\" is exported for all")
                parts = cache.get(key + (attribute,))
                if parts is None:
                    parts = _read_mesh(obj, depsgraph, warn, attribute)
                    cache.put(key + (attribute,), parts)
                meshes[key] = (parts, slots)
            if meshes[key][0]:  # an empty mesh (a geometry-nodes holder) places nothing
                placements.setdefault(key, []).append(_rows(inst.matrix_world))
        elif obj.type == "LIGHT":
            light = light_export.light_dict(obj.data, _rows(inst.matrix_world), warn,
                                            bpy.app.version,
                                            bool(getattr(obj, "visible_camera", False)))
            if light is not None:
                lights.append(light)
        elif obj.type not in ("CAMERA", "EMPTY", "LIGHT_PROBE", "ARMATURE", "LATTICE",
                              "SPEAKER", "GPENCIL"):
            warn(f"object {obj.name}: a {obj.type.lower()} object is not exported")

    scene = depsgraph.scene
    objects = []
    triangles = 0
    meshes = {key: mesh for key, mesh in meshes.items() if key in placements}
    for key, (parts, slots) in meshes.items():
        matrices = placements[key]
        for part in parts:
            name = material_name(slots[part.slot] if part.slot < len(slots) else None)
            objects.append(_placed(part, name, matrices, name in vertex_colors))
            triangles += part.triangles * len(matrices)

    out = {
        "object": objects,
        "material": [dict(params, name=name) for name, params in materials.items()],
        "light": lights,
    }
    background = world_export.background_dict(scene.world, images, warn)
    if background is not None:
        out["background"] = background
    unit_scale = scene.unit_settings.scale_length or 1.0
    if view is not None:
        out["camera"] = view
    elif camera_object is not None:
        out["camera"] = cameras.camera_dict(camera_object, width, height, warn, unit_scale)
    render = {"width": int(width), "height": int(height)}
    render.update(settings or {})
    out["render"] = render
    return Export(out, warnings, len(meshes), sum(len(m) for m in placements.values()), triangles)


def _read_mesh(obj, depsgraph, warn, color_attribute=None):
    try:
        mesh = obj.to_mesh(preserve_all_data_layers=color_attribute is not None,
                           depsgraph=depsgraph)
    except RuntimeError as err:
        warn(f"object {obj.name}: its geometry could not be read ({err})")
        return []
    try:
        return mesh_parts(mesh, color_attribute) if mesh is not None else []
    finally:
        obj.to_mesh_clear()


def _placed(part, material, matrices, colors=False):
    """The scene-file object placing `part` by `matrices`: a mesh placed once, or an
    instance object holding it once for all its placements."""
    obj = dict(part.arrays(colors), material=material)
    if len(matrices) == 1:
        det = float(np.linalg.det(matrices[0][:3, :3]))
        if det != 0.0:
            return dict(obj, type="mesh", matrix=matrices[0])
    return dict(obj, type="instance", transforms=np.stack(matrices))
