"""Reference image empties -> conceptmesh views with fixed cameras.

An image empty (Add > Image > Reference) shows its image in its local XY plane: the image
spans empty_display_size along its larger side, its lower-left corner at
empty_image_offset (in units of the image's width and height; -0.5, -0.5 centres it), and
it is seen the right way round from the side its local X x Y points to. So each empty is an
orthographic camera: the direction it is seen from, image right and image up in the scene,
and the size of one pixel in scene units. conceptmesh's views manifest takes exactly that
(a named view or azimuth/elevation, `scale` in pixels per unit and `origin`, the image point
of the world origin: docs/views.md, "Fixed cameras"), in a frame of the object's own (Y up,
front +Z). The frame is found from the empties (docs/blender.md, "How views are read"), and
the built mesh is placed back through it: it lands on the drawings at their scale.
"""

import json
import math
import os
import re

from mathutils import Matrix, Vector

# Numerical noise of a rotation stored in single precision: directions closer than this
# (radians) are the same direction.
ANGLE_TOL = 2e-4
# Pixels whose width and height in the scene differ by more than this are not square.
SQUARE_TOL = 1e-3

NAMED = {  # view name -> (azimuth, elevation), docs/conventions.md
    "front": (0.0, 0.0),
    "right": (90.0, 0.0),
    "back": (180.0, 0.0),
    "left": (270.0, 0.0),
    "top": (0.0, 90.0),
    "bottom": (0.0, -90.0),
}


class ViewsError(Exception):
    """A reference that cannot be read as a view; the message names it."""


class Reference:
    """One image empty as an orthographic camera in the scene (world coordinates)."""

    def __init__(self, name, image_path, width, height, top_left, right, up, pixel):
        self.name = name
        self.image_path = image_path
        self.width, self.height = width, height
        self.top_left = top_left  # scene point of the image's top-left corner (pixel 0, 0)
        self.right = right  # unit vector: image right
        self.up = up  # unit vector: image up
        self.toward = right.cross(up).normalized()  # from the drawing towards its viewer
        self.pixel = pixel  # scene units per pixel

    def centre(self):
        return self.pixel_to_world(self.width / 2, self.height / 2)

    def pixel_to_world(self, x, y):
        return self.top_left + self.right * (x * self.pixel) - self.up * (y * self.pixel)

    def world_to_pixel(self, p):
        d = p - self.top_left
        return d.dot(self.right) / self.pixel, -d.dot(self.up) / self.pixel


def reference_from_empty(obj, image_path):
    """The camera of image empty `obj` whose image file is `image_path`."""
    img = obj.data
    w, h = int(img.size[0]), int(img.size[1])
    if w <= 0 or h <= 0:
        raise ViewsError('reference "%s": its image "%s" has no pixels (is the file there?)' % (obj.name, img.name))
    # Blender draws the image with its pixel aspect (Image > Display Aspect) and its larger
    # side empty_display_size long.
    ax, ay = img.display_aspect
    ew, eh = w * ax, h * ay
    big = max(ew, eh)
    sx, sy = obj.empty_display_size * ew / big, obj.empty_display_size * eh / big
    ox, oy = obj.empty_image_offset
    m = obj.matrix_world
    x_axis, y_axis, origin = m.col[0].xyz, m.col[1].xyz, m.col[3].xyz
    # Per pixel, in the scene: one step right, one step down.
    step_right = x_axis * (sx / w)
    step_down = -y_axis * (sy / h)
    pw, ph = step_right.length, step_down.length
    if pw <= 0 or ph <= 0:
        raise ViewsError('reference "%s" has no size in the scene (scale or display size 0)' % obj.name)
    if abs(pw - ph) > SQUARE_TOL * max(pw, ph):
        raise ViewsError(
            'reference "%s": its pixels are %.6g x %.6g scene units, not square; give it the same scale '
            "along its X and Y (conceptmesh views have one scale)" % (obj.name, pw, ph)
        )
    right, up = step_right.normalized(), -step_down.normalized()
    if abs(right.dot(up)) > ANGLE_TOL:
        raise ViewsError('reference "%s" is sheared (its X and Y axes are not at right angles in the scene)' % obj.name)
    top_left = origin + x_axis * (sx * ox) + y_axis * (sy * (oy + 1.0))
    return Reference(obj.name, image_path, w, h, top_left, right, up, (pw + ph) / 2)


def _up_candidates(refs):
    cands = [Vector((0, 0, 1))]
    for r in refs:
        cands += [r.up, r.toward, -r.toward]
    for i in range(len(refs)):
        for j in range(i + 1, len(refs)):
            c = refs[i].right.cross(refs[j].right)
            if c.length > 1e-3:
                cands += [c.normalized(), -c.normalized()]
    return cands


def _is_axis_angle(a):
    return abs(a / 90.0 - round(a / 90.0)) * 90.0 < math.degrees(ANGLE_TOL)


def _fits_up(refs, up):
    """Whether every view, with `up` the object's up, has its image up in the vertical plane."""
    return all(abs(r.right.dot(up)) < ANGLE_TOL and r.up.dot(up) > -ANGLE_TOL for r in refs)


def object_frame(refs):
    """The object's frame in the scene: a rotation whose columns are conceptmesh's X, Y (up)
    and Z (front) in scene directions. The up is the scene's +Z when the drawings allow it,
    else the direction they agree on; the front is turned so that as many views as possible
    are named views (front, right, top, ...), nearest to Blender's front (-Y) among equals."""
    ups = [u for u in _up_candidates(refs) if _fits_up(refs, u)]
    if not ups:
        worst = max(refs, key=lambda r: abs(r.right.dot(Vector((0, 0, 1)))))
        raise ViewsError(
            'references do not share an up direction: "%s" is turned about its line of sight '
            "against the others. conceptmesh's views keep the object's up in the image's "
            "vertical plane; turn it back (or turn the others alike)" % worst.name
        )

    def level_views(up):
        return sum(1 for r in refs if abs(r.toward.dot(up)) < ANGLE_TOL or abs(r.toward.dot(up)) > math.cos(ANGLE_TOL))

    up = max(ups, key=level_views)  # max keeps the first of equals: the scene's +Z first
    fronts = []
    for r in refs:
        h = r.toward - up * r.toward.dot(up)
        if h.length < 1e-6:  # a view along the up: its image up turns the front
            h = -r.up if r.toward.dot(up) > 0 else r.up
            h = h - up * h.dot(up)
        if h.length < 1e-6:
            continue
        h.normalize()
        side = up.cross(h)
        fronts += [h, side, -h, -side]
    blender_front = Vector((0, -1, 0)) - up * -up.y
    fronts.append(blender_front.normalized() if blender_front.length > 1e-6 else up.orthogonal().normalized())

    def frame_for(front):
        x = up.cross(front).normalized()
        return Matrix((x, up, front)).transposed()

    def score(front):
        f = frame_for(front)
        named = sum(1 for r in refs if _named_of(*_az_el(r, f)) is not None)
        return (named, front.dot(blender_front))

    return frame_for(max(fronts, key=score))


def _az_el(ref, frame):
    """Azimuth and elevation (degrees) of a view in the object frame (docs/conventions.md)."""
    inv = frame.transposed()
    c = inv @ ref.toward
    u = inv @ ref.up
    flat = math.hypot(c.x, c.z)
    # atan2, not asin: near the vertical asin turns single-precision noise in a matrix
    # (1e-7) into a hundredth of a degree.
    if flat < ANGLE_TOL:
        # Looking along the up, the azimuth is the turn of the image about it.
        el = 90.0 if c.y > 0 else -90.0
        az = math.degrees(math.atan2(-u.x, -u.z) if c.y > 0 else math.atan2(u.x, u.z))
    else:
        el = math.degrees(math.atan2(c.y, flat))
        az = math.degrees(math.atan2(c.x, c.z))
    return az % 360.0, el


def _named_of(az, el):
    tol = math.degrees(ANGLE_TOL)
    for name, (a, e) in NAMED.items():
        if abs(el - e) < tol and abs((az - a + 180.0) % 360.0 - 180.0) < tol:
            return name
    return None


def frame_origin(refs):
    """The scene point closest to every drawing's central line of sight (the middle of the
    object for front/side/top drawings): the object's origin before its pivot is chosen."""
    a = Matrix(((0, 0, 0), (0, 0, 0), (0, 0, 0)))
    b = Vector((0, 0, 0))
    mean = Vector((0, 0, 0))
    for r in refs:
        d = r.toward
        p = Matrix.Identity(3) - Matrix((d * d.x, d * d.y, d * d.z)).transposed()
        c = r.centre()
        a += p
        b += p @ c
        mean += c
    mean /= len(refs)
    eps = 1e-9 * len(refs)  # one drawing alone leaves its line of sight free: its centre
    a += Matrix.Identity(3) * eps
    b += mean * eps
    return a.inverted() @ b


def view_entry(ref, frame, origin):
    """The manifest entry of a view: named or azimuth/elevation, with its fixed camera."""
    az, el = _az_el(ref, frame)
    name = _named_of(az, el)
    # The camera conceptmesh builds from az/el must be the empty's: image right must be
    # horizontal in the object frame (object_frame chose it so), checked to the tolerance.
    inv = frame.transposed()
    r = inv @ ref.right
    a, e = math.radians(az), math.radians(el)
    expect_u = Vector((-math.sin(a) * math.sin(e), math.cos(e), -math.cos(a) * math.sin(e)))
    expect_d = -Vector((math.sin(a) * math.cos(e), math.sin(e), math.cos(a) * math.cos(e)))
    expect_r = expect_d.cross(expect_u)
    if (r - expect_r).length > 4 * ANGLE_TOL:
        raise ViewsError('reference "%s" is turned about its line of sight; conceptmesh cannot take it' % ref.name)
    cx, cy = ref.world_to_pixel(origin)
    entry = {"image": ref.image_path}
    if name is not None:
        entry["view"] = name
    else:
        entry["azimuth"] = az
        entry["elevation"] = el
    entry["scale"] = 1.0 / ref.pixel
    entry["origin"] = [cx, cy]
    return entry


def _key(name, used):
    key = re.sub(r"[^A-Za-z0-9_.-]", "_", name) or "view"
    base, n = key, 2
    while key in used:
        key, n = "%s_%d" % (base, n), n + 1
    used.add(key)
    return key


def _yaml_value(v):
    # JSON scalars and flow lists are YAML; floats in full (repr) read back as the same doubles.
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, list):
        return "[" + ", ".join(_yaml_value(x) for x in v) + "]"
    return json.dumps(v)


def manifest_text(refs, frame, origin, source=""):
    lines = [
        "# Written by the conceptmesh Blender add-on%s: every view's camera is fixed (scale, origin)," % source,
        "# in scene units, in the object frame the add-on places the mesh with.",
        "views:",
    ]
    used = set()
    for r in refs:
        entry = view_entry(r, frame, origin)
        body = ", ".join("%s: %s" % (k, _yaml_value(v)) for k, v in entry.items())
        lines.append("  %s: {%s}" % (json.dumps(_key(r.name, used)), body))
    return "\n".join(lines) + "\n"


def describe(refs, frame):
    """Per reference: which view it is read as (for the panel and the log)."""
    out = []
    for r in refs:
        az, el = _az_el(r, frame)
        name = _named_of(az, el)
        out.append((r.name, name if name else "azimuth %.1f, elevation %.1f" % (az, el)))
    return out


def write_manifest(path, refs, frame, origin):
    with open(path, "w", encoding="utf-8") as f:
        f.write(manifest_text(refs, frame, origin))
    return path


def placement(frame, origin):
    """The object's matrix in the scene for a mesh read from conceptmesh's OBJ with Blender's
    usual axis conversion (forward -Z, up Y: file (x, y, z) -> (x, -z, y))."""
    x, y, z = frame.col[0], frame.col[1], frame.col[2]
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = x[i], -z[i], y[i], origin[i]
    return m


def is_image_empty(obj):
    return obj is not None and obj.type == "EMPTY" and obj.empty_display_type == "IMAGE" and obj.data is not None


def asset_name_from(paths):
    """A name for the asset: the folder of the drawings (examples/spot/front.png -> spot)."""
    for p in paths:
        folder = os.path.basename(os.path.dirname(os.path.abspath(p)))
        if folder:
            return folder
    return "conceptmesh"
