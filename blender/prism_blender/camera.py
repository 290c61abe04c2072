"""Blender cameras (and the viewport's view) as the scene file's `[camera]`."""

import math

import numpy as np

#: Prism's screen sits at distance 1 from the eye: a lens focuses no nearer.
NEAREST_FOCUS = 1.0


def _frame(matrix):
    """Eye, view direction and up of a camera matrix (rows): Blender cameras look
    down their local -Z with +Y up."""
    m = np.asarray(matrix, dtype=float)
    eye = m[:3, 3]
    forward = -m[:3, 2]
    up = m[:3, 1]
    forward = forward / np.linalg.norm(forward)
    up = up - forward * float(np.dot(up, forward))
    return eye, forward, up / np.linalg.norm(up)


def sensor_fit(camera, width, height):
    """Which image side the sensor spans, and the sensor's size along it."""
    fit = camera.sensor_fit
    if fit == "AUTO":
        return ("horizontal" if width >= height else "vertical"), camera.sensor_width
    if fit == "HORIZONTAL":
        return "horizontal", camera.sensor_width
    return "vertical", camera.sensor_height


def focus_distance(camera, eye, forward):
    """The distance to the sharp plane: to the focus object's origin along the view
    axis, as Blender measures it, else the focus distance."""
    target = camera.dof.focus_object
    if target is not None:
        where = np.asarray(target.matrix_world.translation, dtype=float)
        return abs(float(np.dot(where - eye, forward)))
    return float(camera.dof.focus_distance)


def camera_dict(camera_object, width, height, warn, unit_scale=1.0):
    """The `[camera]` of a Blender camera object (evaluated) for a `width` x `height`
    image."""
    cam = camera_object.data
    eye, forward, up = _frame(camera_object.matrix_world)
    out = {"from": eye.tolist(), "at": (eye + forward).tolist(), "up": up.tolist()}
    axis, sensor = sensor_fit(cam, width, height)
    if cam.type == "ORTHO":
        # ortho_scale spans the fitted side; Prism's view_width the horizontal one.
        view = float(cam.ortho_scale)
        if axis == "vertical":
            view *= width / height
        out.update(projection="orthographic", view_width=view)
    else:
        if cam.type != "PERSP":
            warn(f"camera {camera_object.name}: a {cam.type.lower()} camera renders as perspective")
        fov = 2 * math.degrees(math.atan(0.5 * float(sensor) / float(cam.lens)))
        out.update(fov=fov, fov_axis=axis)
        if cam.dof.use_dof and cam.dof.aperture_fstop > 0:
            radius = float(cam.lens) * 1e-3 / (2 * float(cam.dof.aperture_fstop)) / unit_scale
            distance = focus_distance(cam, eye, forward)
            if distance < NEAREST_FOCUS:
                warn(f"camera {camera_object.name}: focus distance {distance:.3g} is nearer "
                     f"than Prism focuses; {NEAREST_FOCUS:g} is used")
                distance = NEAREST_FOCUS
            out.update(aperture=radius, focus_distance=distance)
    if cam.shift_x or cam.shift_y:
        # Blender's shift is in units of the fitted side, as Prism's is.
        if cam.type == "ORTHO":
            warn(f"camera {camera_object.name}: an orthographic camera's shift is not exported")
        else:
            out["shift"] = [float(cam.shift_x), float(cam.shift_y)]
    return out


def view_dict(view_matrix, window_matrix, is_perspective):
    """The `[camera]` of the viewport: the inverse of its view matrix places the eye,
    its projection matrix gives the horizontal field of view (or view width)."""
    world = np.linalg.inv(np.asarray(view_matrix, dtype=float))
    eye, forward, up = _frame(world)
    p = np.asarray(window_matrix, dtype=float)
    out = {"from": eye.tolist(), "at": (eye + forward).tolist(), "up": up.tolist()}
    if is_perspective:
        out.update(fov=2 * math.degrees(math.atan(1 / p[0, 0])), fov_axis="horizontal")
    else:
        out.update(projection="orthographic", view_width=2 / p[0, 0])
    return out
