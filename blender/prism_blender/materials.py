"""Blender materials as Prism's OpenPBR materials (docs/materials.md).

The shader feeding the Material Output's Surface is read: the Principled BSDF (v1 of
Blender 3.x, v2 of 4.x), Diffuse, Glossy, Glass, Emission and Transparent BSDFs, and a
Mix Shader of two of them (blended parameter by parameter; with a Transparent BSDF it
is the cut-out). Any socket may take an Image Texture (its Color, or one channel
through Separate RGB / Separate Color, or its Alpha), and Normal a Normal Map node
over an image. Everything else is a warning naming the node, and its default stands.
"""

import os
import tempfile

import numpy as np

#: The key under which a material says it reads a mesh's vertex colours (the colour
#: attribute's name; "" for the render one): popped by the exporter, which then hands
#: the mesh's colours over with it.
VERTEX_COLORS = "vertex_colors"
#: Cycles' surface for objects without a material: a grey diffuse.
DEFAULT_GREY = 0.8
_CHANNELS = {"Red": "r", "R": "r", "Green": "g", "G": "g", "Blue": "b", "B": "b"}


def default_material():
    """Cycles' default surface: a Lambertian 0.8 grey."""
    return {"color": [DEFAULT_GREY] * 3}


class Images:
    """Blender images as files Prism reads: a file on disk as it is, a packed or
    generated image written once into a folder of this export's own."""

    def __init__(self):
        self._paths = {}
        self._folder = None

    def path(self, image):
        key = image.name
        if key not in self._paths:
            self._paths[key] = self._file_of(image)
        return self._paths[key]

    def _scratch(self):
        if self._folder is None:
            self._folder = tempfile.TemporaryDirectory(prefix="prism-blender-")
        return self._folder.name

    def _file_of(self, image):
        import bpy

        if image.source == "FILE" and image.packed_file is None:
            path = bpy.path.abspath(image.filepath, library=image.library)
            if os.path.isfile(path):
                return os.path.normpath(path)
        safe = "".join(c if c.isalnum() else "_" for c in image.name)
        if image.packed_file is not None:
            ext = os.path.splitext(image.filepath)[1] or ".png"
            path = os.path.join(self._scratch(), safe + ext)
            with open(path, "wb") as f:
                f.write(image.packed_file.data)
            return path
        # Generated or otherwise in memory: saved as PNG (8-bit) or EXR (float).
        float_buffer = bool(getattr(image, "is_float", False))
        path = os.path.join(self._scratch(), safe + (".exr" if float_buffer else ".png"))
        copy = image.copy()
        try:
            copy.filepath_raw = path
            copy.file_format = "OPEN_EXR" if float_buffer else "PNG"
            copy.save()
        finally:
            bpy.data.images.remove(copy)
        return path

    def close(self):
        if self._folder is not None:
            self._folder.cleanup()
            self._folder = None


class _Reader:
    """Reads one material's node tree, warning once per problem."""

    def __init__(self, material, images, warn):
        self.material = material
        self.images = images
        self._warn = warn

    def warn(self, text):
        self._warn(f"material {self.material.name}: {text}")

    def _image(self, node, want_color):
        image = node.image
        if image is None:
            self.warn(f"image texture node {node.name} has no image; its socket's value stands")
            return None
        if node.inputs["Vector"].is_linked:
            self.warn(f"image texture node {node.name}: only the active UV map is exported, "
                      "not the mapping feeding it")
        space = image.colorspace_settings.name
        if want_color and space in ("Non-Color", "Raw", "Linear", "Linear Rec.709"):
            self.warn(f"image {image.name} is {space}; Prism reads colour textures as sRGB")
        if not want_color and space == "sRGB":
            self.warn(f"image {image.name} is sRGB but feeds a value; Prism reads it as data")
        try:
            return self.images.path(image)
        except Exception as err:  # an image that cannot be written out
            self.warn(f"image {image.name} could not be exported ({err})")
            return None

    def value(self, socket, color=False, scale=1.0):
        """A parameter's value: a constant, or a texture table over an image."""
        if not socket.is_linked:
            v = socket.default_value
            if color:
                return [float(c) * scale for c in v[:3]]
            return float(v) * scale
        link = socket.links[0]
        node, output = link.from_node, link.from_socket.name
        if node.bl_idname == "NodeReroute":
            return self.value(node.inputs[0], color, scale)
        if node.bl_idname in ("ShaderNodeVertexColor", "ShaderNodeAttribute") and color \
                and output == "Color" and getattr(node, "attribute_type", "GEOMETRY") == "GEOMETRY":
            name = node.layer_name if node.bl_idname == "ShaderNodeVertexColor" else \
                node.attribute_name
            return {VERTEX_COLORS: name, "factor": [scale] * 3}
        if node.bl_idname == "ShaderNodeTexImage":
            path = self._image(node, color and output == "Color")
            if path is None:
                return self.unlinked(socket, color, scale)
            if color:
                if output != "Color":
                    self.warn(f"{socket.name} takes an image's {output}; Prism reads its colour")
                return {"texture": path, "factor": [scale] * 3}
            channel = "a" if output == "Alpha" else "r"
            return {"texture": path, "channel": channel, "factor": scale}
        if node.bl_idname in ("ShaderNodeSeparateRGB", "ShaderNodeSeparateColor") and not color:
            source = node.inputs[0]
            if source.is_linked and source.links[0].from_node.bl_idname == "ShaderNodeTexImage":
                path = self._image(source.links[0].from_node, False)
                if path is not None:
                    return {"texture": path, "channel": _CHANNELS.get(output, "r"), "factor": scale}
        self.warn(f"{socket.name} is fed by node {node.name} ({node.bl_idname}), which Prism "
                  "does not read; its own value is used")
        return self.unlinked(socket, color, scale)

    @staticmethod
    def unlinked(socket, color, scale):
        v = socket.default_value
        return [float(c) * scale for c in v[:3]] if color else float(v) * scale

    def constant(self, socket):
        """A socket's value where only a constant fits (texture: its default, warned)."""
        if socket.is_linked:
            self.warn(f"{socket.name} takes a constant in Prism; the node feeding it is ignored")
        v = socket.default_value
        return float(v) if isinstance(v, float) else [float(c) for c in v[:3]]

    def normal(self, socket):
        """A tangent-space normal map file from a Normal Map node over an image."""
        if not socket.is_linked:
            return None
        node = socket.links[0].from_node
        if node.bl_idname == "ShaderNodeNormalMap":
            if node.space != "TANGENT":
                self.warn(f"normal map node {node.name} is in {node.space} space; Prism reads "
                          "tangent-space maps")
                return None
            if abs(node.inputs["Strength"].default_value - 1.0) > 1e-6:
                self.warn(f"normal map node {node.name}: its strength is not exported")
            color = node.inputs["Color"]
            if color.is_linked and color.links[0].from_node.bl_idname == "ShaderNodeTexImage":
                return self._image(color.links[0].from_node, False)
        self.warn(f"{socket.name} is fed by node {node.name} ({node.bl_idname}), which Prism "
                  "does not read (bump maps are not exported)")
        return None


def _ior_of_f0(f0):
    r = np.sqrt(np.clip(f0, 0.0, 0.999))
    return float((1 + r) / (1 - r))


def _mean_fresnel(ior):
    """The hemispherical mean of a dielectric's Fresnel reflectance, 2 int F(mu) mu dmu:
    the share of diffuse light a specular layer of this IOR keeps from the base."""
    mu = (np.arange(256) + 0.5) / 256
    sin_t2 = (1 - mu * mu) / (ior * ior)
    cos_t = np.sqrt(np.clip(1 - sin_t2, 0, 1))
    rs = (mu - ior * cos_t) / (mu + ior * cos_t)
    rp = (ior * mu - cos_t) / (ior * mu + cos_t)
    f = np.where(sin_t2 >= 1, 1.0, 0.5 * (rs * rs + rp * rp))
    return float(2 * np.mean(f * mu))


def _lift(color, k):
    if isinstance(color, dict):
        factor = color.get("factor", [1.0, 1.0, 1.0])
        return dict(color, factor=[c * k for c in factor])
    return [c * k for c in color]


def _squared(color):
    if isinstance(color, dict):
        return color  # a texture's square is not a texture Prism reads; the tint stands
    return [c * c for c in color]


def _tint(base):
    """Principled v1's tint: the base colour over its luminance."""
    if isinstance(base, dict):
        return [1.0, 1.0, 1.0]
    lum = 0.3 * base[0] + 0.6 * base[1] + 0.1 * base[2]
    return [c / lum for c in base] if lum > 0 else [1.0, 1.0, 1.0]


def _principled(reader, node):
    inputs = node.inputs
    out = {"base_color": reader.value(inputs["Base Color"], color=True),
           "base_metalness": reader.value(inputs["Metallic"]),
           "specular_roughness": reader.value(inputs["Roughness"]),
           "geometry_opacity": reader.value(inputs["Alpha"])}
    if "Specular" in inputs:  # v1 (Blender 3.x)
        transmission = reader.constant(inputs["Transmission"])
        if transmission > 0:
            out["specular_ior"] = reader.constant(inputs["IOR"])
            out["transmission_weight"] = transmission
        else:
            specular = reader.constant(inputs["Specular"])
            if specular <= 0:
                out["specular_weight"] = 0.0
            else:
                ior = _ior_of_f0(0.08 * specular)
                out["specular_ior"] = ior
                # v1 lays its specular over an undimmed diffuse (its energy gain), while
                # OpenPBR's base keeps what the specular leaves: lift the base by what
                # the specular takes on average, so the look stays v1's.
                metal = out["base_metalness"]
                if not isinstance(metal, dict) and metal < 1:
                    lift = 1 / (1 - _mean_fresnel(ior))
                    out["base_color"] = _lift(out["base_color"], 1 + (lift - 1) * (1 - metal))
        tint = reader.constant(inputs["Specular Tint"])
        if tint > 0:
            t = _tint(out["base_color"])
            out["specular_color"] = [1 - tint + tint * c for c in t]
        subsurface = reader.constant(inputs["Subsurface"])
        coat, coat_roughness = inputs["Clearcoat"], inputs["Clearcoat Roughness"]
        sheen = reader.constant(inputs["Sheen"])
        sheen_tint = reader.constant(inputs["Sheen Tint"])
        emission, anisotropic = inputs["Emission"], inputs["Anisotropic"]
        coat_normal = inputs["Clearcoat Normal"]
        coat_ior = 1.5
        sheen_color = [1 - sheen_tint + sheen_tint * c for c in _tint(out["base_color"])]
        sheen_roughness = 0.5
    else:  # v2 (Blender 4.x)
        out["specular_ior"] = reader.constant(inputs["IOR"])
        level = reader.constant(inputs["Specular IOR Level"])
        if abs(level - 0.5) > 1e-6:
            out["specular_weight"] = 2 * level
        out["specular_color"] = reader.value(inputs["Specular Tint"], color=True)
        transmission = reader.constant(inputs["Transmission Weight"])
        if transmission > 0:
            out["transmission_weight"] = transmission
        subsurface = reader.constant(inputs["Subsurface Weight"])
        coat, coat_roughness = inputs["Coat Weight"], inputs["Coat Roughness"]
        coat_ior = reader.constant(inputs["Coat IOR"])
        out["coat_color"] = reader.value(inputs["Coat Tint"], color=True)
        sheen = reader.constant(inputs["Sheen Weight"])
        sheen_color = reader.value(inputs["Sheen Tint"], color=True)
        sheen_roughness = reader.constant(inputs["Sheen Roughness"])
        emission, anisotropic = inputs["Emission Color"], inputs["Anisotropic"]
        coat_normal = inputs["Coat Normal"]
        if "Thin Film Thickness" in inputs:
            film = reader.constant(inputs["Thin Film Thickness"])
            if film > 0:
                out.update(thin_film_weight=1.0, thin_film_thickness=film / 1000.0,
                           thin_film_ior=reader.constant(inputs["Thin Film IOR"]))
    if out.get("transmission_weight", 0) > 0:
        # The Principled BSDF tints what it transmits by its base colour. v1 tints at
        # every crossing of the surface, Prism once, on the way in: squared, the tint
        # of a path that enters and leaves a solid is v1's. v2 tints once, as Prism.
        v1 = "Specular" in inputs
        out["transmission_color"] = _squared(out["base_color"]) if v1 else out["base_color"]
    if subsurface > 0:
        radius = np.asarray(reader.constant(inputs["Subsurface Radius"]), dtype=float)
        biggest = float(radius.max())
        out.update(subsurface_weight=subsurface,
                   subsurface_color=out["base_color"] if "Subsurface Color" not in inputs
                   else reader.value(inputs["Subsurface Color"], color=True),
                   subsurface_radius=biggest,
                   subsurface_radius_scale=(radius / biggest).tolist() if biggest > 0 else [1, 1, 1])
    coat_weight = reader.value(coat)
    if coat_weight != 0.0:
        out.update(coat_weight=coat_weight, coat_roughness=reader.value(coat_roughness),
                   coat_ior=coat_ior)
        coat_map = reader.normal(coat_normal)
        if coat_map:
            out["geometry_coat_normal"] = coat_map
    if sheen > 0:
        out.update(fuzz_weight=sheen, fuzz_color=sheen_color, fuzz_roughness=sheen_roughness)
    aniso = reader.value(anisotropic)
    if aniso != 0.0:
        out["specular_roughness_anisotropy"] = aniso
    strength = reader.constant(inputs["Emission Strength"])
    color = reader.value(emission, color=True)
    if strength > 0 and (isinstance(color, dict) or any(c > 0 for c in color)):
        out.update(emission_color=color, emission_luminance=strength)
    normal = reader.normal(inputs["Normal"])
    if normal:
        out["geometry_normal"] = normal
    return out


def _shader(reader, node):
    """The OpenPBR parameters of the shader node `node`, or None if it has none."""
    kind = node.bl_idname
    if kind == "ShaderNodeBsdfPrincipled":
        return _principled(reader, node)
    if kind == "ShaderNodeBsdfDiffuse":
        return {"base_color": reader.value(node.inputs["Color"], color=True),
                "base_diffuse_roughness": reader.value(node.inputs["Roughness"]),
                "specular_weight": 0.0}
    if kind in ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic"):
        out = {"base_color": reader.value(node.inputs["Color"], color=True),
               "base_metalness": 1.0, "specular_roughness": reader.value(node.inputs["Roughness"])}
        if "Anisotropy" in node.inputs and node.inputs["Anisotropy"].default_value:
            out["specular_roughness_anisotropy"] = abs(reader.constant(node.inputs["Anisotropy"]))
        return out
    if kind == "ShaderNodeBsdfGlass":
        return {"transmission_weight": 1.0,
                "transmission_color": _squared(reader.value(node.inputs["Color"], color=True)),
                "specular_roughness": reader.value(node.inputs["Roughness"]),
                "specular_ior": reader.constant(node.inputs["IOR"])}
    if kind == "ShaderNodeEmission":
        return {"base_weight": 0.0, "specular_weight": 0.0,
                "emission_color": reader.value(node.inputs["Color"], color=True),
                "emission_luminance": reader.constant(node.inputs["Strength"])}
    if kind == "ShaderNodeBsdfTransparent":
        return {"geometry_opacity": 0.0}
    if kind == "ShaderNodeMixShader":
        return _mix(reader, node)
    if kind == "NodeReroute":
        return _surface(reader, node.inputs[0])
    reader.warn(f"shader node {node.name} ({kind}) is not exported; a grey diffuse stands in")
    return None


def _surface(reader, socket):
    if not socket.is_linked:
        return None
    return _shader(reader, socket.links[0].from_node)


def _mix(reader, node):
    fac = reader.constant(node.inputs[0])
    a, b = _surface(reader, node.inputs[1]), _surface(reader, node.inputs[2])
    transparent = {"geometry_opacity": 0.0}
    if b == transparent and a is not None:  # a cut-out: Transparent mixed in by fac
        return dict(a, geometry_opacity=_scaled(a.get("geometry_opacity", 1.0), 1 - fac))
    if a == transparent and b is not None:
        return dict(b, geometry_opacity=_scaled(b.get("geometry_opacity", 1.0), fac))
    if a is None or b is None:
        return a or b
    base_a, base_b = a, b
    out = {}
    for key in set(base_a) | set(base_b):
        va, vb = base_a.get(key, _DEFAULTS.get(key)), base_b.get(key, _DEFAULTS.get(key))
        out[key] = _blend(va, vb, fac)
        if out[key] is None:
            reader.warn(f"mix shader {node.name}: {key} differs in a way Prism cannot blend; "
                        f"the {'second' if fac >= 0.5 else 'first'} shader's stands")
            out[key] = vb if fac >= 0.5 else va
    return out


#: The OpenPBR defaults a mix blends towards where one side leaves a key unset.
_DEFAULTS = {
    "base_weight": 1.0, "base_color": [0.8, 0.8, 0.8], "base_metalness": 0.0,
    "base_diffuse_roughness": 0.0, "specular_weight": 1.0, "specular_color": [1.0, 1.0, 1.0],
    "specular_roughness": 0.3, "specular_ior": 1.5, "specular_roughness_anisotropy": 0.0,
    "transmission_weight": 0.0, "transmission_color": [1.0, 1.0, 1.0], "coat_weight": 0.0,
    "coat_roughness": 0.0, "coat_ior": 1.6, "coat_color": [1.0, 1.0, 1.0], "fuzz_weight": 0.0,
    "fuzz_color": [1.0, 1.0, 1.0], "fuzz_roughness": 0.5, "emission_luminance": 0.0,
    "emission_color": [1.0, 1.0, 1.0], "geometry_opacity": 1.0, "subsurface_weight": 0.0,
}


def _scaled(value, k):
    if isinstance(value, dict):
        return dict(value, factor=value.get("factor", 1.0) * k)
    return value * k


def _blend(a, b, t):
    if a is None or b is None or isinstance(a, (dict, str)) or isinstance(b, (dict, str)):
        return a if a == b else None
    if isinstance(a, list) or isinstance(b, list):
        a = a if isinstance(a, list) else [a] * 3
        b = b if isinstance(b, list) else [b] * 3
        return [x + (y - x) * t for x, y in zip(a, b)]
    return a + (b - a) * t


def material_dict(material, images, warn):
    """The scene-file `[[material]]` (without its name) of a Blender material."""
    if material is None:
        return default_material()
    reader = _Reader(material, images, warn)
    if not material.use_nodes or material.node_tree is None:
        return {"type": "openpbr", "base_color": [float(c) for c in material.diffuse_color[:3]],
                "base_metalness": float(material.metallic),
                "specular_roughness": float(material.roughness)}
    tree = material.node_tree
    output = tree.get_output_node("CYCLES") or tree.get_output_node("ALL")
    if output is None:
        warn(f"material {material.name}: no Material Output node; a grey diffuse stands in")
        return default_material()
    params = _surface(reader, output.inputs["Surface"])
    if params is None:
        return default_material()
    params = {k: v for k, v in params.items() if v is not None}
    attribute = None
    for key, value in list(params.items()):
        if isinstance(value, dict) and VERTEX_COLORS in value:
            if key == "base_color" and attribute is None:
                # The vertex colours multiply the albedo: the base colour is their factor.
                attribute = value[VERTEX_COLORS]
                params[key] = value["factor"]
            else:
                reader.warn(f"{key} reads vertex colours, which Prism takes as the base "
                            "colour only; its default stands")
                del params[key]
    out = _lambertian(params) or dict(params, type="openpbr")
    if attribute is not None:
        out[VERTEX_COLORS] = attribute
    return out


def _lambertian(params):
    """A plain material where OpenPBR parameters say only "a Lambertian of this
    colour" (a Diffuse BSDF of roughness 0): the same light, without an OpenPBR
    material's set-up at every hit. None for anything more."""
    if set(params) - {"base_color", "base_diffuse_roughness", "specular_weight"}:
        return None
    if params.get("specular_weight", 1.0) != 0.0 or params.get("base_diffuse_roughness", 0.0) != 0.0:
        return None
    color = params.get("base_color", [DEFAULT_GREY] * 3)
    if isinstance(color, dict):
        if color.get("factor", [1.0] * 3) != [1.0] * 3:
            return None
        return {"texture": color["texture"]}
    return {"color": color}
