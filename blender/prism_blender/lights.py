"""Blender lights as Prism lights, in Blender's units as Cycles reads them.

A light's power P (watts) becomes:

- point: radiant intensity I = P / (4 pi) W/sr with inverse-square falloff; with a
  radius r, a sphere light of radiance I / (pi r^2), which shows the same intensity;
- spot: the point light's intensity, times Cycles' cone: a smoothstep over the blend
  region, times (before Blender 4.0) the cosine from the axis;
- area: radiance L = P / (4 A) over its area A (square, rectangle, disk; an ellipse
  as the disk of its area), emitting on its front (local -Z) side as Cycles does;
  from Blender 4.0, L = P / (pi A) (Cycles' power of an area light was corrected);
- sun: its strength is the irradiance (W/m^2) on a surface facing it.

The light's colour multiplies, and so does an Emission node's colour and strength
when the light uses nodes.
"""

import math

import numpy as np


def _axis(matrix, column):
    return np.asarray([matrix[0][column], matrix[1][column], matrix[2][column]], dtype=float)


def _position(matrix):
    return [float(matrix[0][3]), float(matrix[1][3]), float(matrix[2][3])]


def _unit(v):
    n = float(np.linalg.norm(v))
    return (v / n).tolist() if n > 0 else None


def _emission(light, warn):
    """The colour times the node tree's Emission colour and strength."""
    color = np.asarray(light.color[:3], dtype=float)
    if getattr(light, "use_nodes", False) and light.node_tree is not None:
        for node in light.node_tree.nodes:
            if node.bl_idname == "ShaderNodeEmission":
                c, s = node.inputs["Color"], node.inputs["Strength"]
                if c.is_linked or s.is_linked:
                    warn(f"light {light.name}: a node feeding its Emission is not exported")
                color = color * np.asarray(c.default_value[:3]) * float(s.default_value)
                break
    return color


#: The Blender version whose Cycles took an area light's power as pi L A (it was 4 L A)
#: and dropped the spot light's cosine.
CONVENTIONS_4 = (4, 0, 0)


def light_dict(light, matrix, warn, version=(3, 4, 0), camera_visible=False):
    """The scene-file `[[light]]` of `light` (bpy.types.Light) placed by `matrix`
    (its object's world matrix, rows), in the conventions of Blender `version`, or
    None for a light that gives nothing. `camera_visible` is the object's ray
    visibility for the camera (off by default in Blender: lights light the scene and
    show in reflections, but the camera does not see them)."""
    out = _light_dict(light, matrix, warn, tuple(version) >= CONVENTIONS_4)
    if out is not None and out["type"] in ("sphere", "quad", "disk") and not camera_visible:
        out["camera_visible"] = False
    return out


def _light_dict(light, matrix, warn, modern):
    color = _emission(light, warn)
    power = float(light.energy)
    if power <= 0 or not np.any(color > 0):
        return None
    forward = _unit(-_axis(matrix, 2))
    kind = light.type
    if kind == "SUN":
        if forward is None:
            return None
        return {"type": "directional", "direction": forward, "color": color.tolist(),
                "intensity": power}
    if kind in ("POINT", "SPOT"):
        intensity = power / (4 * math.pi)
        radius = float(getattr(light, "shadow_soft_size", 0.0))
        # The light's own scale does not size its radius in Cycles.
        if kind == "POINT" and radius > 0:
            return {"type": "sphere", "center": _position(matrix), "radius": radius,
                    "color": color.tolist(), "intensity": intensity / (math.pi * radius * radius)}
        out = {"type": "point", "position": _position(matrix), "color": color.tolist(),
               "intensity": intensity, "falloff": "inverse_square"}
        if kind == "SPOT":
            if forward is None:
                return None
            half = min(float(light.spot_size) / 2, math.radians(89.99))
            cos_outer = math.cos(half)
            cos_inner = min(1.0, cos_outer + (1 - cos_outer) * float(light.spot_blend))
            out.update(type="spot", direction=forward, angle=math.degrees(half),
                       inner_angle=math.degrees(math.acos(cos_inner)),
                       edge="smooth" if modern else "smooth_cosine")
            if radius > 0:
                warn(f"spot light {light.name}: its radius (soft shadows) is not exported; "
                     "Prism's spots are points")
        return out
    if kind == "AREA":
        per_area = power / (math.pi if modern else 4.0)
        sx = float(light.size)
        sy = float(light.size_y) if light.shape in ("RECTANGLE", "ELLIPSE") else sx
        u = _axis(matrix, 0) * sx
        v = -_axis(matrix, 1) * sy  # u x v faces local -Z, where Cycles' area lights shine
        normal = np.cross(u, v)
        if float(np.linalg.norm(normal)) == 0:
            return None
        spread = float(getattr(light, "spread", math.pi))
        if spread < math.pi - 1e-4:
            warn(f"area light {light.name}: its spread of {math.degrees(spread):.0f} degrees "
                 "is not exported; it emits over the whole hemisphere")
        if light.shape in ("SQUARE", "RECTANGLE"):
            area = float(np.linalg.norm(normal))
            return {"type": "quad", "center": _position(matrix), "edge1": u.tolist(),
                    "edge2": v.tolist(), "color": color.tolist(), "intensity": per_area / area}
        # Disk and ellipse: a disk of the ellipse's area, facing its normal.
        lu, lv = float(np.linalg.norm(u)), float(np.linalg.norm(v))
        if light.shape == "ELLIPSE" or abs(lu - lv) > 1e-6 * max(lu, lv):
            warn(f"area light {light.name}: an ellipse is exported as the disk of its area")
        radius = 0.5 * math.sqrt(lu * lv)
        area = math.pi * radius * radius
        return {"type": "disk", "center": _position(matrix), "normal": _unit(normal),
                "radius": radius, "color": color.tolist(), "intensity": per_area / area}
    warn(f"light {light.name}: type {kind} is not exported")
    return None
