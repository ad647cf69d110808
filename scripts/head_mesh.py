#!/usr/bin/env python3
"""The referee's head of the tennis set (thesis 7.4: "the referee is
represented by the head that is a surface imported into the L-system").

Writes scenes/meshes/head.obj and scenes/meshes/head.mtl: a stylised
human head -- skull and face, jaw, nose, ears, eyes with irises, brows,
mouth, a hair cap, a neck and a shirt collar -- about 0.25 m wide (ears
included), 0.3 m high, facing +z, y up, the neck's base at the origin.
lmfilm reads flat triangles (normals are not used), so the surfaces are
fine enough to look smooth: about 6,700 triangles.

Colours (head.mtl) keep away from the vision colours of the ball and of
the two players (materials 12, 10, 11): their normalised colours are more
than 0.2 apart (thesis 3.1.2, rule 1), so a player's vision never takes
the referee for the ball.

Standard library only; the output is the same bytes on every run:
    python3 scripts/head_mesh.py            # from the repository's root
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "scenes", "meshes")

# name: (Kd, Ks, Ns)
MATERIALS = [
    ("head_skin", (0.87, 0.70, 0.62), 0.08, 12),
    ("head_hair", (0.36, 0.34, 0.33), 0.15, 30),
    ("head_eye_white", (0.95, 0.95, 0.93), 0.4, 60),
    ("head_iris", (0.16, 0.24, 0.26), 0.6, 80),
    ("head_lips", (0.62, 0.40, 0.45), 0.15, 20),
    ("head_collar", (0.93, 0.93, 0.95), 0.05, 8),
]

# the skull: centre and semi-axes (x wide, y high, z deep)
CY = 0.18
AX, AY, AZ = 0.093, 0.122, 0.108


def skull(u, v, w):
    """Point of the skull/face surface in the direction (u, v, w) of the
    unit sphere (v up, w forward): an ellipsoid with a narrower jaw, a
    slightly flattened face and a rounder back of the head."""
    k = 1.0 - 0.26 * max(0.0, -v) ** 1.6  # jaw narrows below the middle
    x = AX * u * k
    y = CY + AY * v
    front = max(0.0, w)
    z = AZ * w * (1.0 - 0.10 * front ** 4)  # flatter face
    if w < 0.0:
        z *= 1.0 + 0.06 * max(0.0, v)  # rounder back of the skull
        z *= 1.0 - 0.25 * max(0.0, -v) ** 2  # tucked in above the neck
    if w > 0.0 and v < 0.0:
        z *= 1.0 - 0.12 * (-v) ** 2 * (1 - w)  # chin forward of the jaw
    return (x, y, z)


def sphere_dir(theta, phi):
    """Unit direction: theta from the top (0) to the bottom (pi), phi the
    azimuth from the front (+z) towards +x."""
    s = math.sin(theta)
    return (s * math.sin(phi), math.cos(theta), s * math.cos(phi))


class Mesh:
    def __init__(self):
        self.v = []
        self.groups = []  # (material, [faces])

    def vert(self, p):
        self.v.append(p)
        return len(self.v)  # OBJ numbers from 1

    def group(self, material):
        faces = []
        self.groups.append((material, faces))
        return faces

    def grid(self, material, rows, closed_top, closed_bottom):
        """Faces of a lat-long grid: rows[i][j] vertex numbers, j wraps.
        A top/bottom row of one repeated pole vertex gives triangles."""
        faces = self.group(material)
        n = len(rows[0])
        for i in range(len(rows) - 1):
            a, b = rows[i], rows[i + 1]
            for j in range(n):
                j1 = (j + 1) % n
                # counter-clockwise seen from outside (rows go downwards,
                # columns from the front towards +x, i.e. to the right)
                if a[j] == a[j1]:
                    faces.append((a[j], b[j], b[j1]))
                elif b[j] == b[j1]:
                    faces.append((a[j], b[j], a[j1]))
                else:
                    faces.append((a[j], b[j], b[j1]))
                    faces.append((a[j], b[j1], a[j1]))
        return faces

    def surface(self, material, f, nlat, nlon):
        """A closed surface p = f(theta, phi), poles included."""
        rows = []
        for i in range(nlat + 1):
            theta = math.pi * i / nlat
            if i == 0 or i == nlat:
                pole = self.vert(f(theta, 0.0))
                rows.append([pole] * nlon)
            else:
                rows.append(
                    [self.vert(f(theta, 2 * math.pi * j / nlon)) for j in range(nlon)]
                )
        self.grid(material, rows, True, True)

    def ellipsoid(self, material, centre, radii, rot, nlat, nlon):
        def f(theta, phi):
            d = sphere_dir(theta, phi)
            local = (d[0] * radii[0], d[1] * radii[1], d[2] * radii[2])
            r = rotate(rot, local)
            return (centre[0] + r[0], centre[1] + r[1], centre[2] + r[2])

        self.surface(material, f, nlat, nlon)

    def cylinder(self, material, centre, radius, y0, y1, n, bands):
        rows = []
        rows.append([self.vert((centre[0], y1, centre[1]))] * n)
        for i in range(bands + 1):
            y = y1 + (y0 - y1) * i / bands
            rows.append(
                [
                    self.vert(
                        (
                            centre[0] + radius * math.sin(2 * math.pi * j / n),
                            y,
                            centre[1] + radius * math.cos(2 * math.pi * j / n),
                        )
                    )
                    for j in range(n)
                ]
            )
        rows.append([self.vert((centre[0], y0, centre[1]))] * n)
        self.grid(material, rows, True, True)

    def triangles(self):
        return sum(len(f) for _, f in self.groups)


def rotate(rot, p):
    """rot = (yaw about y, pitch about x) in degrees, pitch first."""
    yaw, pitch = (math.radians(a) for a in rot)
    x, y, z = p
    y, z = y * math.cos(pitch) - z * math.sin(pitch), y * math.sin(pitch) + z * math.cos(pitch)
    x, z = x * math.cos(yaw) + z * math.sin(yaw), -x * math.sin(yaw) + z * math.cos(yaw)
    return (x, y, z)


def on_skull(v, phi, inset):
    """The skull point at height v (sin of the latitude) and azimuth phi
    from the front, moved `inset` towards the skull's centre."""
    theta = math.acos(max(-1.0, min(1.0, v)))
    p = skull(*sphere_dir(theta, phi))
    c = (0.0, CY, 0.0)
    d = [p[i] - c[i] for i in range(3)]
    n = math.sqrt(sum(x * x for x in d))
    return tuple(p[i] - inset * d[i] / n for i in range(3))


def build():
    m = Mesh()

    # skull and face: 30 bands, 44 around
    m.surface("head_skin", lambda t, p: skull(*sphere_dir(t, p)), 30, 44)

    # hair cap: a shell over the skull, down to the forehead in front, to
    # above the ears at the sides and to the nape behind
    nlon, nlat = 44, 12
    rows = [[m.vert(on_skull(1.0, 0.0, -0.012))] * nlon]
    for i in range(1, nlat + 1):
        row = []
        for j in range(nlon):
            phi = 2 * math.pi * j / nlon
            c = math.cos(phi)  # 1 in front, -1 behind
            side = abs(math.sin(phi))
            theta_max = math.radians(62 + 50 * (1 - c) / 2 + 8 * side * (c > 0))
            theta = theta_max * i / nlat
            # thicker on top, thin at the edge
            lift = 0.004 + 0.012 * math.cos(theta * math.pi / 2 / theta_max) ** 2
            p = skull(*sphere_dir(theta, phi))
            d = (p[0], p[1] - CY, p[2])
            n = math.sqrt(sum(x * x for x in d))
            row.append(m.vert(tuple(p[k] + lift * d[k] / n for k in range(3))))
        rows.append(row)
    m.grid("head_hair", rows, True, False)

    # eyes: white balls and dark irises, brows above them
    for s in (-1, 1):
        phi = s * math.radians(24)
        c = on_skull(0.16, phi, 0.012)
        m.ellipsoid("head_eye_white", c, (0.017, 0.015, 0.016), (0, 0), 12, 16)
        ic = (c[0] + 0.003 * s, c[1], c[2] + 0.0115)
        m.ellipsoid("head_iris", ic, (0.0085, 0.0085, 0.0065), (0, 0), 8, 12)
        b = on_skull(0.36, s * math.radians(25), -0.002)
        m.ellipsoid("head_hair", b, (0.024, 0.0055, 0.008), (s * 20, 0), 6, 12)

    # nose: a wedge-like ellipsoid tilted forward from the brow line
    n = on_skull(-0.10, 0.0, 0.008)
    m.ellipsoid("head_skin", n, (0.013, 0.030, 0.017), (0, -18), 12, 16)
    m.ellipsoid("head_skin", (n[0], n[1] - 0.022, n[2] + 0.006), (0.016, 0.010, 0.011), (0, 0), 8, 12)

    # mouth
    mo = on_skull(-0.50, 0.0, 0.004)
    m.ellipsoid("head_lips", mo, (0.030, 0.0075, 0.011), (0, 0), 8, 16)

    # ears: flat ellipsoids on the sides, tilted back a little
    for s in (-1, 1):
        e = on_skull(0.02, s * math.radians(88), 0.004)
        m.ellipsoid(
            "head_skin",
            (e[0] + 0.008 * s, e[1], e[2] - 0.008),
            (0.016, 0.036, 0.023),
            (s * -15, 12),
            10,
            16,
        )

    # neck (from the origin into the head) and the shirt's collar
    m.cylinder("head_skin", (0.0, -0.012), 0.050, 0.0, CY - 0.02, 24, 6)
    m.cylinder("head_collar", (0.0, -0.012), 0.060, 0.0, 0.045, 24, 2)
    return m


def write(m):
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "head.mtl"), "w", newline="\n") as f:
        f.write("# The referee's head: scripts/head_mesh.py writes this file.\n")
        for name, kd, ks, ns in MATERIALS:
            ka = tuple(0.2 * c for c in kd)
            f.write(f"newmtl {name}\n")
            f.write("Ka %.4f %.4f %.4f\n" % ka)
            f.write("Kd %.4f %.4f %.4f\n" % kd)
            f.write("Ks %.4f %.4f %.4f\n" % (ks, ks, ks))
            f.write(f"Ns {ns}\nd 1\nillum 2\n")
    with open(os.path.join(OUT, "head.obj"), "w", newline="\n") as f:
        f.write("# The referee's head (thesis 7.4): scripts/head_mesh.py writes this file.\n")
        f.write("# y up, facing +z, the neck's base at the origin; metres.\n")
        f.write(f"# {len(m.v)} vertices, {m.triangles()} triangles\n")
        f.write("mtllib head.mtl\no head\n")
        for p in m.v:
            f.write("v %.5f %.5f %.5f\n" % p)
        for material, faces in m.groups:
            f.write(f"usemtl {material}\n")
            for a, b, c in faces:
                f.write(f"f {a} {b} {c}\n")


def main():
    m = build()
    write(m)
    xs = [p[0] for p in m.v]
    ys = [p[1] for p in m.v]
    zs = [p[2] for p in m.v]
    print(
        "head.obj: %d vertices, %d triangles, x %.3f..%.3f, y %.3f..%.3f, z %.3f..%.3f"
        % (len(m.v), m.triangles(), min(xs), max(xs), min(ys), max(ys), min(zs), max(zs)),
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
