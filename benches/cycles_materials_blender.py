"""Blender side of benches/cycles_materials.py: import a glTF model, report how Blender's
glTF importer mapped its material extensions, set up the same camera and environment as
Prism's command line, and render it with Cycles (CPU, no adaptive sampling, no denoising,
no clamping, a one-pixel box filter) to linear float OpenEXR.

Run by cycles_materials.py as

  blender -b --factory-startup --python benches/cycles_materials_blender.py -- \
      --model M.glb --env env.hdr --look-from X,Y,Z --look-at X,Y,Z --fov HFOV \
      --width W --height H --spp N --seeds 1,2 --out-prefix OUT [--report R.json] \
      [--no-fixups] [--env-rotations -90] [--save-blend F.blend] [--no-render]

Coordinates given on the command line are glTF's (Y up, as Prism's); the importer turns
glTF (x, y, z) into Blender (x, -z, y), and so does this script for the camera. The
environment image is Prism's equirectangular convention (centre column along glTF -z,
top along +y); Blender's world texture has its centre column along Blender +X, so the
texture's lookup vector is turned by --env-rotations degrees about Blender's Z (default
-90, the mapping that cycles_materials.py `orient` verifies). With several rotations,
one image per rotation is written (OUT-rot<deg>-<seed>.exr).

Fix-ups (unless --no-fixups), applied after the import so that Cycles 3.4 renders what
the glTF extension means, each reported in the JSON:
  - clearcoat: Cycles 3.4's Principled clearcoat is Disney's, 0.25 x clearcoat x a GGX
    coat of F0 0.04 (svm_closure.h: bsdf_alloc(..., 0.25f * clearcoat * weight)); the
    importer passes clearcoatFactor straight through, so the coat reflects a quarter of
    what glTF says. The Clearcoat input is fed 4 x the imported value through a Math
    node (a linked input is not clamped to 1).
  - volume: the importer puts attenuationColor c and 1 / attenuationDistance d into a
    Volume Absorption node, whose coefficient is density x (1 - colour); glTF's is
    -ln(c) / d per channel. The node gets density k = max(-ln c) / d and colour
    1 + ln(c) / (k d), which is glTF's coefficient exactly.
  - alphaMode MASK: Cycles ignores Blender's Alpha Clip and blends by alpha; the alpha
    is stepped at alphaCutoff (1 where alpha >= cutoff, else 0), as glTF says.
  - alphaMode BLEND: stepped at 0.5 too. This one is Prism's reading of an alpha
    texture under BLEND, not glTF's: Prism cuts it at 0.5 (docs/formats.md; a constant
    BLEND alpha is a presence instead, which none of these models uses), glTF blends;
    it is made the same in Cycles so that the material extensions are compared, and
    reported.
  - IOR exactly 1 on a transmissive material: 1.001. Cycles 3.4's rough GGX refraction
    is singular at an index of 1 and renders such glass nearly black (a rough sphere
    of IOR 1.0: 0.12 where IOR 1.001 and 1.01 give 0.50, as Prism does at 1.0).
  - distribution: Principled BSDFs use Multiscatter GGX (energy-conserving rough
    reflection and refraction, as OpenPBR's lobes are) instead of the importer's GGX.
"""

import numpy

numpy.bool = bool  # Debian's numpy has no numpy.bool alias, which the importer uses.

import argparse
import json
import math
import struct
import sys

import bpy
from mathutils import Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="cycles_materials_blender.py")
    p.add_argument("--model", required=True)
    p.add_argument("--env", required=True)
    p.add_argument("--env-strength", type=float, default=1.0)
    p.add_argument("--env-rotations", default="-90")
    p.add_argument("--look-from", required=True)
    p.add_argument("--look-at", required=True)
    p.add_argument("--fov", type=float, required=True)
    p.add_argument("--width", type=int, default=200)
    p.add_argument("--height", type=int, default=200)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--seeds", default="1")
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--bounces", type=int, default=64)
    p.add_argument("--out-prefix", default="/tmp/cycles")
    p.add_argument("--report")
    p.add_argument("--no-fixups", action="store_true")
    p.add_argument("--save-blend")
    p.add_argument("--no-render", action="store_true")
    return p.parse_args(argv)


def vec3(text):
    x, y, z = (float(v) for v in text.split(","))
    return x, y, z


def to_blender(p):
    x, y, z = p
    return Vector((x, -z, y))


def gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        length = struct.unpack("<I", data[12:16])[0]
        return json.loads(data[20:20 + length])
    return json.loads(data)


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras):
        for block in list(coll):
            coll.remove(block)


def principled_of(mat):
    if not mat.use_nodes:
        return None
    for node in mat.node_tree.nodes:
        if node.type == "BSDF_PRINCIPLED":
            return node
    return None


def socket_value(sock):
    if sock.is_linked:
        return "linked"
    v = sock.default_value
    try:
        return [round(float(c), 5) for c in v]
    except TypeError:
        return round(float(v), 5)


def close(a, b, tol=1e-3):
    return isinstance(a, float) and abs(a - b) <= tol * max(1.0, abs(b))


STATUS_ORDER = {"mapped": 0, "mapped, fixed up": 1, "approximate": 2, "not imported": 3}


def classify(gmat, bmat):
    """Per extension of one glTF material: (status, note) from the imported nodes."""
    out = {}
    exts = gmat.get("extensions", {}) or {}
    pr = principled_of(bmat) if bmat else None
    nodes = list(bmat.node_tree.nodes) if bmat and bmat.use_nodes else []
    types = {n.type for n in nodes}
    for ext, e in exts.items():
        if pr is None:
            out[ext] = ("not imported", "no Principled BSDF")
            continue
        if ext == "KHR_materials_clearcoat":
            v = socket_value(pr.inputs["Clearcoat"])
            want = e.get("clearcoatFactor", 0.0)
            if v == "linked" or close(v, want):
                out[ext] = ("mapped, fixed up",
                            "Principled Clearcoat = clearcoatFactor, but Cycles 3.4's coat "
                            "is Disney's 0.25 x coat: fed 4 x")
            else:
                out[ext] = ("not imported", f"Clearcoat {v}, glTF {want}")
        elif ext == "KHR_materials_sheen":
            if "BSDF_VELVET" in types:
                out[ext] = ("approximate",
                            "a Velvet BSDF (sigma = sheenRoughness) added to the Principled "
                            "BSDF: not glTF's Charlie sheen layered over the base")
            else:
                out[ext] = ("not imported", "no sheen node")
        elif ext == "KHR_materials_specular":
            spec = socket_value(pr.inputs["Specular"])
            factor = e.get("specularFactor", 1.0)
            note = ("Principled Specular from luminance(specularColorFactor) and the IOR "
                    f"only (here {spec}); specularFactor {factor} is not used and the colour "
                    "becomes a Specular Tint towards the base colour")
            out[ext] = ("approximate", note)
        elif ext == "KHR_materials_transmission":
            v = socket_value(pr.inputs["Transmission"])
            want = e.get("transmissionFactor", 0.0)
            ok = v == "linked" or close(v, want)
            out[ext] = ("mapped" if ok else "not imported",
                        f"Principled Transmission {v}")
        elif ext == "KHR_materials_ior":
            v = socket_value(pr.inputs["IOR"])
            want = e.get("ior", 1.5)
            out[ext] = ("mapped" if close(v, want) else "not imported", f"Principled IOR {v}")
        elif ext == "KHR_materials_volume":
            has_att = "attenuationDistance" in e
            if not has_att:
                out[ext] = ("mapped", "thickness only (no attenuation): nothing to render")
            elif "VOLUME_ABSORPTION" in types:
                out[ext] = ("mapped, fixed up",
                            "Volume Absorption of colour c, density 1/d: coefficient "
                            "(1 - c)/d, not glTF's -ln(c)/d: converted")
            else:
                out[ext] = ("not imported", "no Volume Absorption node")
        elif ext == "KHR_texture_transform":
            out[ext] = ("mapped", "Mapping node")
        else:
            out[ext] = ("mapped" if ext in ("KHR_materials_emissive_strength",) else
                        "unchecked", "")
    return out


def fix_clearcoat(mat, pr):
    tree = mat.node_tree
    sock = pr.inputs["Clearcoat"]
    mul = tree.nodes.new("ShaderNodeMath")
    mul.operation = "MULTIPLY"
    mul.label = "Cycles 3.4 clearcoat x4 (bench fix-up)"
    mul.inputs[1].default_value = 4.0
    if sock.is_linked:
        src = sock.links[0].from_socket
        tree.links.remove(sock.links[0])
        tree.links.new(src, mul.inputs[0])
    else:
        mul.inputs[0].default_value = sock.default_value
    tree.links.new(mul.outputs[0], sock)


def fix_volume(mat):
    notes = []
    for node in mat.node_tree.nodes:
        if node.type != "VOLUME_ABSORPTION":
            continue
        c = [max(float(v), 1e-6) for v in node.inputs["Color"].default_value[:3]]
        density = float(node.inputs["Density"].default_value)
        if density <= 0:
            continue
        sigma = [-math.log(min(v, 1.0)) * density for v in c]
        k = max(sigma)
        if k <= 0:
            continue
        colour = [1.0 - s / k for s in sigma]
        node.inputs["Color"].default_value = colour + [1.0]
        node.inputs["Density"].default_value = k
        notes.append("colour " + ",".join(f"{v:.3g}" for v in c) + f" density {density:.3g} -> "
                     "colour " + ",".join(f"{v:.3g}" for v in colour) + f" density {k:.3g}")
    return notes


def fix_alpha(mat, pr, cutoff):
    """Cycles ignores the material's blend mode and threshold and blends by alpha: make
    the Principled BSDF's alpha 1 where it is at least `cutoff`, else 0."""
    tree = mat.node_tree
    sock = pr.inputs["Alpha"]
    if sock.is_linked:
        step = tree.nodes.new("ShaderNodeMath")
        step.operation = "GREATER_THAN"
        step.label = f"alpha >= {cutoff} (bench fix-up)"
        step.inputs[1].default_value = cutoff - 1e-6
        src = sock.links[0].from_socket
        tree.links.remove(sock.links[0])
        tree.links.new(src, step.inputs[0])
        tree.links.new(step.outputs[0], sock)
    else:
        sock.default_value = 1.0 if sock.default_value >= cutoff else 0.0


def inspect_and_fix(model, fixups):
    g = gltf_json(model)
    report = {"extensionsUsed": g.get("extensionsUsed", []), "materials": {}, "fixups": []}
    for i, gmat in enumerate(g.get("materials", [])):
        name = gmat.get("name", f"Material_{i}")
        bmat = bpy.data.materials.get(name)
        cls = classify(gmat, bmat)
        pr = principled_of(bmat) if bmat else None
        inputs = {}
        if pr is not None:
            for key in ("Base Color", "Metallic", "Roughness", "Specular", "Specular Tint",
                        "IOR", "Transmission", "Clearcoat", "Clearcoat Roughness", "Sheen"):
                inputs[key] = socket_value(pr.inputs[key])
        report["materials"][name] = {
            "found": bmat is not None,
            "extensions": {k: {"status": s, "note": n} for k, (s, n) in cls.items()},
            "principled": inputs,
            "nodes": sorted({n.type for n in bmat.node_tree.nodes}) if bmat and bmat.use_nodes else [],
        }
        if not fixups or bmat is None or pr is None:
            continue
        exts = gmat.get("extensions", {}) or {}
        mode = gmat.get("alphaMode", "OPAQUE")
        if mode == "MASK":
            cutoff = gmat.get("alphaCutoff", 0.5)
            fix_alpha(bmat, pr, cutoff)
            report["fixups"].append(f"{name}: alphaMode MASK: alpha stepped at {cutoff} "
                                    "(Cycles ignores the importer's Alpha Clip)")
        elif mode == "BLEND":
            fix_alpha(bmat, pr, 0.5)
            report["fixups"].append(f"{name}: alphaMode BLEND: alpha stepped at 0.5, Prism's "
                                    "documented reading of BLEND as a cut-out (glTF blends)")
        if "KHR_materials_clearcoat" in exts:
            fix_clearcoat(bmat, pr)
            report["fixups"].append(f"{name}: clearcoat x4")
        if "KHR_materials_volume" in exts:
            notes = fix_volume(bmat)
            if notes:
                report["fixups"].append(f"{name}: volume absorption to Beer's law: {'; '.join(notes)}")
    if fixups:
        for mat in bpy.data.materials:
            pr = principled_of(mat)
            if pr is None:
                continue
            ior, tr = pr.inputs["IOR"], pr.inputs["Transmission"]
            if (not ior.is_linked and abs(ior.default_value - 1.0) < 1e-4
                    and (tr.is_linked or tr.default_value > 0)):
                ior.default_value = 1.001
                report["fixups"].append(f"{mat.name}: IOR 1.0 -> 1.001 (Cycles 3.4's rough "
                                        "refraction is dark at exactly 1)")
        count = 0
        for mat in bpy.data.materials:
            pr = principled_of(mat)
            if pr is not None and pr.distribution != "MULTI_GGX":
                pr.distribution = "MULTI_GGX"
                count += 1
        report["fixups"].append(f"{count} Principled BSDFs: distribution Multiscatter GGX")
    return report


def setup_world(env, strength, rotation_deg):
    world = bpy.data.worlds.new("bench-env") if not bpy.context.scene.world else bpy.context.scene.world
    bpy.context.scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    coord = nt.nodes.new("ShaderNodeTexCoord")
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    tex = nt.nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(env, check_existing=True)
    tex.image.colorspace_settings.name = "Linear"
    tex.interpolation = "Linear"
    tex.projection = "EQUIRECTANGULAR"
    bg = nt.nodes.new("ShaderNodeBackground")
    bg.inputs["Strength"].default_value = strength
    out = nt.nodes.new("ShaderNodeOutputWorld")
    nt.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
    nt.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
    nt.links.new(bg.outputs["Background"], out.inputs["Surface"])
    world.cycles.sampling_method = "MANUAL"
    world.cycles.sample_map_resolution = 1024
    return mapping


def set_rotation(mapping, deg):
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(deg))


def setup_camera(look_from, look_at, fov):
    cam_data = bpy.data.cameras.new("bench-camera")
    cam_data.lens_unit = "FOV"
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.angle = math.radians(fov)
    cam_data.clip_start = 1e-3
    cam_data.clip_end = 1e5
    cam = bpy.data.objects.new("bench-camera", cam_data)
    bpy.context.scene.collection.objects.link(cam)
    eye = to_blender(look_from)
    target = to_blender(look_at)
    cam.location = eye
    cam.rotation_euler = (target - eye).to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.camera = cam


def setup_cycles(args):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = args.spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.max_bounces = args.bounces
    c.diffuse_bounces = args.bounces
    c.glossy_bounces = args.bounces
    c.transmission_bounces = args.bounces
    c.volume_bounces = args.bounces
    c.transparent_max_bounces = args.bounces
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.filter_type = "BOX"
    c.filter_width = 1.0  # a box of one pixel: each pixel the plain mean of its samples
    c.use_animated_seed = False
    r = scene.render
    r.resolution_x = args.width
    r.resolution_y = args.height
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1
    r.film_transparent = False
    r.use_persistent_data = False
    if args.threads > 0:
        r.threads_mode = "FIXED"
        r.threads = args.threads
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.image_settings.color_mode = "RGB"
    r.image_settings.exr_codec = "ZIP"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.sequencer_colorspace_settings.name = "Linear"


def main():
    args = parse_args()
    clear_scene()
    bpy.ops.import_scene.gltf(filepath=args.model)
    report = inspect_and_fix(args.model, not args.no_fixups)
    report["blender"] = bpy.app.version_string
    mapping = setup_world(args.env, args.env_strength, 0.0)
    setup_camera(vec3(args.look_from), vec3(args.look_at), args.fov)
    setup_cycles(args)
    scene = bpy.context.scene
    rotations = [float(v) for v in args.env_rotations.split(",")]
    seeds = [int(v) for v in args.seeds.split(",")]
    if args.report:
        with open(args.report, "w") as f:
            json.dump(report, f, indent=1)
    if args.save_blend:
        set_rotation(mapping, rotations[0])
        scene.cycles.seed = seeds[0]
        scene.render.filepath = args.out_prefix
        scene.render.use_file_extension = True
        bpy.ops.wm.save_as_mainfile(filepath=args.save_blend, compress=False)
    if args.no_render:
        return
    for rot in rotations:
        set_rotation(mapping, rot)
        for seed in seeds:
            scene.cycles.seed = seed
            tag = f"-rot{rot:g}" if len(rotations) > 1 else ""
            scene.render.filepath = f"{args.out_prefix}{tag}-{seed}.exr"
            bpy.ops.render.render(write_still=True)


main()
