"""Blender's world as the scene file's `[background]`: a colour times a strength, or an
equirectangular Environment Texture with its Mapping node's rotation about Z.

Blender's scenes are Z-up, and Prism takes them as they are: the environment's top
looks along +Z, and the centre column of Blender's equirectangular image looks along
+X (Cycles takes a direction d to u = 1/2 - atan2(d.y, d.x) / 2 pi).
"""

import math

UP = [0.0, 0.0, 1.0]
FORWARD = [1.0, 0.0, 0.0]


def _rotated_forward(angle):
    """FORWARD turned by `angle` radians about +Z (a Mapping node's Z rotation, which
    turns the texture's lookup direction the other way)."""
    c, s = math.cos(-angle), math.sin(-angle)
    x, y = FORWARD[0], FORWARD[1]
    return [c * x - s * y, s * x + c * y, 0.0]


def _mapping_rotation(node, warn, world):
    """The Z rotation of a Mapping node feeding an Environment Texture's Vector."""
    vector = node.inputs["Vector"]
    if not vector.is_linked:
        return 0.0
    mapping = vector.links[0].from_node
    if mapping.bl_idname == "ShaderNodeTexCoord":
        return 0.0
    if mapping.bl_idname != "ShaderNodeMapping":
        warn(f"world {world.name}: node {mapping.name} before the environment is not exported")
        return 0.0
    rotation = mapping.inputs["Rotation"].default_value
    if abs(rotation[0]) > 1e-6 or abs(rotation[1]) > 1e-6:
        warn(f"world {world.name}: only the mapping's rotation about Z is exported")
    if mapping.vector_type not in ("POINT", "TEXTURE"):
        warn(f"world {world.name}: mapping type {mapping.vector_type} is read as Point")
    angle = float(rotation[2])
    return -angle if mapping.vector_type == "TEXTURE" else angle


def background_dict(world, images, warn):
    """The `[background]` of a Blender world (None: black)."""
    if world is None:
        return None
    if not world.use_nodes or world.node_tree is None:
        return {"color": [float(c) for c in world.color[:3]]}
    output = world.node_tree.get_output_node("CYCLES") or world.node_tree.get_output_node("ALL")
    surface = output.inputs["Surface"] if output is not None else None
    if surface is None or not surface.is_linked:
        return None
    node = surface.links[0].from_node
    if node.bl_idname != "ShaderNodeBackground":
        warn(f"world {world.name}: shader {node.name} ({node.bl_idname}) is not exported")
        return None
    color, strength = node.inputs["Color"], node.inputs["Strength"]
    if strength.is_linked:
        warn(f"world {world.name}: the node feeding the background's strength is not exported")
    intensity = float(strength.default_value)
    if not color.is_linked:
        return {"color": [float(c) for c in color.default_value[:3]], "intensity": intensity}
    source = color.links[0].from_node
    if source.bl_idname == "ShaderNodeTexEnvironment" and source.image is not None:
        if source.projection != "EQUIRECTANGULAR":
            warn(f"world {world.name}: a {source.projection.lower()} environment is read as "
                 "equirectangular")
        angle = _mapping_rotation(source, warn, world)
        return {"image": images.path(source.image), "up": UP, "forward": _rotated_forward(angle),
                "intensity": intensity}
    warn(f"world {world.name}: node {source.name} ({source.bl_idname}) feeding the background "
         "is not exported; its colour stands")
    return {"color": [float(c) for c in color.default_value[:3]], "intensity": intensity}
