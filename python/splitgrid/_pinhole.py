"""Pinhole camera rays with the semantics of Open3D's RaycastingScene.create_rays_pinhole.

The library's own camera (sg-render's) takes a vertical field of view and makes unit
directions; Open3D's takes a horizontal one (or an intrinsic matrix) and makes directions whose
component along the viewing axis is 1, so that ``t_hit`` is the depth along that axis. This
module follows Open3D, so that code written for it gets the same rays.
"""

import numpy as np


def _plain(value):
    """An Open3D tensor as numpy; anything else as it is."""
    return value.numpy() if hasattr(value, "numpy") and not isinstance(value, np.ndarray) else value


def _vector3(value, name):
    array = np.asarray(_plain(value), dtype=np.float64)
    if array.shape != (3,) or not np.all(np.isfinite(array)):
        raise ValueError(f"{name}: expected 3 finite numbers, got {value!r}")
    return array


def _matrix(value, name, shape):
    array = np.asarray(_plain(value), dtype=np.float64)
    if array.shape != shape or not np.all(np.isfinite(array)):
        raise ValueError(f"{name}: expected a finite {shape[0]}x{shape[1]} matrix, "
                         f"got shape {array.shape}")
    return array


def _size(value, name):
    if isinstance(value, bool) or int(value) != value or value < 1:
        raise ValueError(f"{name}: expected a positive whole number of pixels, got {value!r}")
    return int(value)


def _rays(intrinsic, extrinsic, width_px, height_px):
    """Rays of the camera K = intrinsic, [R | t] = extrinsic[:3] (world to camera)."""
    rotation = extrinsic[:3, :3]
    translation = extrinsic[:3, 3]
    origin = -rotation.T @ translation
    # Pixel (x, y) is looked at through its centre (x + 0.5, y + 0.5), row y from the top.
    u, v = np.meshgrid(np.arange(width_px) + 0.5, np.arange(height_px) + 0.5)
    pixels = np.stack([u, v, np.ones_like(u)], axis=-1)
    camera_directions = pixels @ np.linalg.inv(intrinsic).T
    rays = np.empty((height_px, width_px, 6), dtype=np.float32)
    rays[..., :3] = origin
    rays[..., 3:] = camera_directions @ rotation
    return rays


def create_rays_pinhole(*args, **kwargs):
    """Rays through the pixel centres of a pinhole camera (Open3D's create_rays_pinhole).

    Two forms, as in Open3D::

        create_rays_pinhole(fov_deg, center, eye, up, width_px, height_px)
        create_rays_pinhole(intrinsic_matrix, extrinsic_matrix, width_px, height_px)

    Parameters
    ----------
    fov_deg : float
        Horizontal field of view in degrees, in (0, 180).
    center : array_like, shape (3,)
        The point the camera looks at.
    eye : array_like, shape (3,)
        The camera's position.
    up : array_like, shape (3,)
        The up vector; image columns run along ``up x (center - eye)`` and rows
        along ``(center - eye) x columns``, as in Open3D.
    intrinsic_matrix : array_like, shape (3, 3)
        Upper triangular camera matrix K (focal lengths, principal point).
    extrinsic_matrix : array_like, shape (4, 4)
        World-to-camera transform [R | t].
    width_px, height_px : int
        Image size in pixels.

    Returns
    -------
    numpy.ndarray, float32, shape (height_px, width_px, 6)
        Origin and direction of the ray through pixel (x, y) at ``[y, x]``. The
        direction's component along the viewing axis is 1 (it is not unit
        length), so cast_rays' ``t_hit`` is the depth along that axis.
    """
    names = ("fov_deg", "center", "eye", "up", "width_px", "height_px")
    matrix_names = ("intrinsic_matrix", "extrinsic_matrix", "width_px", "height_px")
    matrix_form = "intrinsic_matrix" in kwargs or (
        len(args) >= 1 and np.ndim(_plain(args[0])) == 2)
    chosen = matrix_names if matrix_form else names
    if len(args) > len(chosen):
        raise TypeError(f"create_rays_pinhole() takes {len(chosen)} arguments in this form "
                        f"({', '.join(chosen)}), got {len(args)}")
    values = dict(zip(chosen, args))
    for key, value in kwargs.items():
        if key not in chosen:
            raise TypeError(f"create_rays_pinhole() got an unexpected keyword argument '{key}'")
        if key in values:
            raise TypeError(f"create_rays_pinhole() got multiple values for argument '{key}'")
        values[key] = value
    missing = [name for name in chosen if name not in values]
    if missing:
        raise TypeError(f"create_rays_pinhole() missing arguments: {', '.join(missing)}")
    width_px = _size(values["width_px"], "width_px")
    height_px = _size(values["height_px"], "height_px")

    if matrix_form:
        intrinsic = _matrix(values["intrinsic_matrix"], "intrinsic_matrix", (3, 3))
        extrinsic = _matrix(values["extrinsic_matrix"], "extrinsic_matrix", (4, 4))
        if np.linalg.det(intrinsic) == 0:
            raise ValueError("intrinsic_matrix: the matrix is singular")
        return _rays(intrinsic, extrinsic, width_px, height_px)

    fov_deg = float(values["fov_deg"])
    if not 0 < fov_deg < 180:
        raise ValueError(f"fov_deg: expected a horizontal field of view in (0, 180) degrees, "
                         f"got {values['fov_deg']!r}")
    center = _vector3(values["center"], "center")
    eye = _vector3(values["eye"], "eye")
    up = _vector3(values["up"], "up")
    forward = center - eye
    if not np.any(forward):
        raise ValueError("center and eye: the camera looks at its own position")
    forward /= np.linalg.norm(forward)
    right = np.cross(up, forward)
    if np.linalg.norm(right) == 0:
        raise ValueError("up: parallel to the viewing direction center - eye")
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    rotation = np.stack([right, down, forward])
    extrinsic = np.eye(4)
    extrinsic[:3, :3] = rotation
    extrinsic[:3, 3] = -rotation @ eye
    focal = 0.5 * width_px / np.tan(np.radians(0.5 * fov_deg))
    intrinsic = np.array([[focal, 0.0, 0.5 * width_px],
                          [0.0, focal, 0.5 * height_px],
                          [0.0, 0.0, 1.0]])
    return _rays(intrinsic, extrinsic, width_px, height_px)
