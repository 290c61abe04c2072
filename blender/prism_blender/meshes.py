"""Blender meshes as the arrays Prism's scene takes, read through the public API only
(``calc_loop_triangles`` and ``foreach_get`` into NumPy).

A mesh becomes one part per material slot it uses. Where it has no smooth faces and no
texture coordinates its vertices are Blender's own; otherwise every face corner (loop)
is a vertex of its own, so split normals (auto smooth, sharp edges, custom normals) and
UV seams come across exactly as Blender shades them.
"""

import numpy as np


class MeshPart:
    """One material slot's triangles of a mesh, in the object's own space."""

    __slots__ = ("slot", "vertices", "faces", "normals", "uvs", "colors")

    def __init__(self, slot, vertices, faces, normals=None, uvs=None, colors=None):
        self.slot = slot
        self.vertices = vertices
        self.faces = faces
        self.normals = normals
        self.uvs = uvs
        self.colors = colors

    @property
    def triangles(self):
        return len(self.faces)

    def arrays(self, colors=False):
        """The keys of a scene-file mesh object given as arrays (with its vertex
        colours when its material reads them)."""
        out = {"vertices": self.vertices, "faces": self.faces}
        if self.normals is not None:
            out["normals"] = self.normals
        if self.uvs is not None:
            out["uvs"] = self.uvs
        if colors and self.colors is not None:
            out["colors"] = self.colors
        return out


def _get(collection, attribute, count, width, dtype):
    out = np.empty(count * width, dtype=dtype)
    if count:
        collection.foreach_get(attribute, out)
    return out.reshape(count, width) if width > 1 else out


def _smooth_faces(mesh, tris):
    """Whether any triangle is shaded smooth (Blender 3.x flag, or 4.1's attribute)."""
    if not tris:
        return False
    try:
        return bool(_get(mesh.loop_triangles, "use_smooth", tris, 1, bool).any())
    except (AttributeError, TypeError):
        sharp = mesh.attributes.get("sharp_face")
        if sharp is None:
            return True
        return not bool(_get(sharp.data, "value", len(sharp.data), 1, bool).all())


def _corner_normals(mesh, loops):
    """One normal per face corner, as Blender shades the mesh."""
    corner = getattr(mesh, "corner_normals", None)  # Blender 4.1+
    if corner is not None:
        return _get(corner, "vector", loops, 3, np.float32)
    if hasattr(mesh, "calc_normals_split"):  # 3.x to 4.0: auto smooth, custom normals
        mesh.calc_normals_split()
    return _get(mesh.loops, "normal", loops, 3, np.float32)


def _has_custom_normals(mesh):
    return bool(getattr(mesh, "has_custom_normals", False))


def _color_attribute(mesh, name):
    """The colour attribute `name` of `mesh` (or its render colour attribute when
    `name` is empty), or None."""
    attributes = getattr(mesh, "color_attributes", None)
    if attributes is None or not len(attributes):
        return None
    if name:
        return attributes.get(name)
    index = getattr(attributes, "render_color_index", -1)
    if 0 <= index < len(attributes):
        return attributes[index]
    return attributes.active_color


def _corner_colors(mesh, attribute, corner_vertex):
    """One linear RGB colour per face corner of a colour attribute on points or
    corners."""
    data = attribute.data
    rgba = _get(data, "color", len(data), 4, np.float32)
    if attribute.domain == "POINT":
        rgba = rgba[corner_vertex]
    elif attribute.domain != "CORNER":
        return None
    return np.ascontiguousarray(rgba[:, :3])


def mesh_parts(mesh, color_attribute=None):
    """The triangles of `mesh` (an evaluated mesh, as ``Object.to_mesh`` gives), one
    `MeshPart` per material slot used, in slot order; with `color_attribute` (a name,
    or "" for the render colour attribute) its vertex colours too."""
    mesh.calc_loop_triangles()
    tris = len(mesh.loop_triangles)
    if tris == 0:
        return []
    loops = len(mesh.loops)
    corners = _get(mesh.loop_triangles, "loops", tris, 3, np.int32)
    slots = _get(mesh.loop_triangles, "material_index", tris, 1, np.int32)
    positions = _get(mesh.vertices, "co", len(mesh.vertices), 3, np.float32)
    corner_vertex = _get(mesh.loops, "vertex_index", loops, 1, np.int32)
    uv_layer = mesh.uv_layers.active if len(mesh.uv_layers) else None
    smooth = _smooth_faces(mesh, tris) or _has_custom_normals(mesh)
    attribute = None if color_attribute is None else _color_attribute(mesh, color_attribute)
    colors = None if attribute is None else _corner_colors(mesh, attribute, corner_vertex)

    if not smooth and uv_layer is None and colors is None:
        vertices, faces, normals, uvs = positions, corner_vertex[corners], None, None
    else:
        vertices = positions[corner_vertex]
        faces = corners
        normals = _corner_normals(mesh, loops) if smooth else None
        uvs = _get(uv_layer.data, "uv", loops, 2, np.float32) if uv_layer is not None else None

    used = np.unique(slots)
    if len(used) == 1:
        return [MeshPart(int(used[0]), vertices, faces.astype(np.uint32), normals, uvs, colors)]
    parts = []
    for slot in used:
        part_faces = faces[slots == slot]
        keep, inverse = np.unique(part_faces, return_inverse=True)
        parts.append(
            MeshPart(
                int(slot),
                vertices[keep],
                inverse.reshape(-1, 3).astype(np.uint32),
                None if normals is None else normals[keep],
                None if uvs is None else uvs[keep],
                None if colors is None else colors[keep],
            )
        )
    return parts
