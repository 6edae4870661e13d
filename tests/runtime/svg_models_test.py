#!/usr/bin/env python3
"""The SVG drawing of every shipped model (runtime/include/mechgen/io/svg.h), as a person sees it.

usage: svg_models_test.py <models dir> <rsvg-convert or ''> <mechgen_view> <model>.so...

For every model (a shared object of the generated model, named <model>.so, that mechgen_view
loads: its drawing is the per-model <model>_sweep's, byte for byte, as sweep_view_test.sh
checks for the four-bar): run `mechgen_view sweep` with --svg and --csv over its default range; the SVG must be
well-formed XML, every <circle> must have cx, cy and r (a circle without them is a stray dot
at the origin in a static renderer), the mechanism must be drawn, and rsvg-convert (when
given) must render it to a PNG of the SVG's size. Then checks from the geometry, against
positions computed here by hand from the model's parameters and the CSV's first row (not by
the code under test): a binary link is one bar whose ends are its joints, the four-bar's
coupler a plate with corners B, C, P, ground pivots only at revolute joints to the ground (a
slider's guide point is none), a slider's block centred on its pin and aligned with its
guide, pitch circles and rollers of their radii at their centres.
"""
import csv
import math
import os
import re
import struct
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

NS = "{http://www.w3.org/2000/svg}"
failures = []
TOL = 0.05  # pixels (coordinates are printed with 2 decimals)


def fail(model, msg):
    failures.append(f"{model}: {msg}")
    print(f"FAIL {model}: {msg}")


def first_row(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: float(v) for k, v in rows[0].items() if k != "status"}


class Drawing:
    def __init__(self, root):
        self.root = root
        self.x_min = float(root.get("data-x-min"))
        self.y_max = float(root.get("data-y-max"))
        self.scale = float(root.get("data-scale"))

    def px(self, p):
        return ((p[0] - self.x_min) * self.scale, (self.y_max - p[1]) * self.scale + 30)

    def group(self, gid):
        for g in self.root.iter(NS + "g"):
            if g.get("id") == gid:
                return g
        return None

    def link_groups(self, link):
        """The still (first configuration) groups of `link` in the mechanism, with their transforms."""
        mech = self.group("mechanism")
        out = []
        for g in mech.findall(NS + "g"):
            if g.get("data-link") == link:
                out.append(g)
        return out


def transform_of(g):
    m = re.fullmatch(r"translate\(([-\d.e]+) ([-\d.e]+)\) rotate\(([-\d.e]+)\)", g.get("transform"))
    tx, ty, a = (float(v) for v in m.groups())
    c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
    return lambda x, y: (tx + c * x - s * y, ty + s * x + c * y)


def near(p, q, tol=TOL):
    return math.hypot(p[0] - q[0], p[1] - q[1]) <= tol


def same_points(got, want, tol=TOL):
    return len(got) == len(want) and all(any(near(g, w, tol) for g in got) for w in want)


def bars(d, link):
    """Every body <line> of the link (layer 0), as pixel end points."""
    out = []
    for g in d.link_groups(link):
        if g.get("class") != "link":
            continue
        t = transform_of(g)
        for e in g.findall(NS + "line"):
            if float(e.get("stroke-width", "0")) >= 6:
                out.append([t(float(e.get("x1")), float(e.get("y1"))), t(float(e.get("x2")), float(e.get("y2")))])
    return out


def polygons(d, link, layer_class=None):
    out = []
    for g in d.link_groups(link):
        if layer_class is not None and g.get("class") != layer_class:
            continue
        t = transform_of(g)
        for e in g.findall(NS + "polygon"):
            pts = [tuple(float(v) for v in p.split(",")) for p in e.get("points").split()]
            out.append([t(*p) for p in pts])
    return out


def circles(d, link):
    out = []
    for g in d.link_groups(link):
        t = transform_of(g)
        for e in g.findall(NS + "circle"):
            out.append((t(float(e.get("cx")), float(e.get("cy"))), float(e.get("r"))))
    return out


def pivot_apexes(d):
    """Apexes of the ground pivots' triangles (pixels)."""
    g = d.group("ground")
    out = []
    for e in g.findall(NS + "polygon"):
        pts = [tuple(float(v) for v in p.split(",")) for p in e.get("points").split()]
        if len(pts) == 3:
            out.append(pts[0])
    return out


def rot(t, x, y):
    return (x * math.cos(t) - y * math.sin(t), x * math.sin(t) + y * math.cos(t))


def check_binary(model, d, link, a, b):
    got = bars(d, link)
    if len(got) != 1 or not same_points(got[0], [d.px(a), d.px(b)]):
        fail(model, f"{link} should be one bar from {d.px(a)} to {d.px(b)}, drawn: {got}")


def check_fourbar(d, row):
    a, b, c, dd, xi, eta = 1.0, 3.5, 3.0, 4.0, 1.5, 1.0  # models/fourbar.yaml
    t1, t2, t3 = row["theta_crank"], row["theta_coupler"], row["theta_rocker"]
    A, D = (0.0, 0.0), (dd, 0.0)
    B = (a * math.cos(t1), a * math.sin(t1))
    C = (B[0] + b * math.cos(t2), B[1] + b * math.sin(t2))
    C2 = (dd + c * math.cos(t3), c * math.sin(t3))
    assert math.hypot(C[0] - C2[0], C[1] - C2[1]) < 1e-8, "the CSV's angles do not close the loop"
    off = rot(t2, xi, eta)
    P = (B[0] + off[0], B[1] + off[1])
    assert math.hypot(P[0] - row["coupler.P.x"], P[1] - row["coupler.P.y"]) < 1e-8
    check_binary("fourbar", d, "crank", A, B)
    check_binary("fourbar", d, "rocker", D, C)
    plates = polygons(d, "coupler", "link")
    if len(plates) != 1 or not same_points(plates[0], [d.px(B), d.px(C), d.px(P)]):
        fail("fourbar", f"coupler should be the plate B C P, drawn: {plates}")
    if not same_points(pivot_apexes(d), [d.px(A), d.px(D)]):
        fail("fourbar", f"ground pivots at A and D expected, drawn at {pivot_apexes(d)}")


def block_of(d, link):
    """The slider block of `link`: (centre, direction of its long side) in pixels."""
    for poly in polygons(d, link):
        if len(poly) != 4:
            continue
        cx = sum(p[0] for p in poly) / 4
        cy = sum(p[1] for p in poly) / 4
        s1 = (poly[1][0] - poly[0][0], poly[1][1] - poly[0][1])
        s2 = (poly[2][0] - poly[1][0], poly[2][1] - poly[1][1])
        long_side = s1 if math.hypot(*s1) >= math.hypot(*s2) else s2
        return (cx, cy), math.atan2(-long_side[1], long_side[0])  # model orientation (y up)
    return None


def parallel(angle, theta):
    return abs(math.sin(angle - theta)) < 1e-3


def check_slider_crank(d, row):
    a, b, e = 1.0, 3.2, 0.4  # models/slider_crank.yaml
    t1, t2, s = row["theta_crank"], row["theta_rod"], row["s_slide"]
    O, S = (0.0, 0.0), (0.0, e)
    B = (a * math.cos(t1), a * math.sin(t1))
    C = (s, e)
    assert math.hypot(B[0] + b * math.cos(t2) - C[0], B[1] + b * math.sin(t2) - C[1]) < 1e-8
    check_binary("slider_crank", d, "crank", O, B)
    check_binary("slider_crank", d, "rod", B, C)
    blk = block_of(d, "slider")
    if blk is None or not near(blk[0], d.px(C)) or not parallel(blk[1], 0.0):
        fail("slider_crank", f"the slider's block should be centred on C {d.px(C)} along x, drawn: {blk}")
    apexes = pivot_apexes(d)
    if not same_points(apexes, [d.px(O)]):
        fail("slider_crank", f"one ground pivot, at O, expected (the guide point S is none), drawn at {apexes}")
    # The rails: two lines parallel to the guide, one either side of it.
    inner = d.group("ground").find(NS + "g")
    t = transform_of(inner)
    ys = []
    for e2 in inner.findall(NS + "line"):
        p1 = t(float(e2.get("x1")), float(e2.get("y1")))
        p2 = t(float(e2.get("x2")), float(e2.get("y2")))
        if abs(p1[1] - p2[1]) < 1e-6 and abs(p1[0] - p2[0]) > 50:
            ys.append(p1[1])
    ys.sort()
    yS = d.px(S)[1]
    if len(ys) != 2 or not (ys[0] < yS < ys[1]) or abs((ys[0] + ys[1]) / 2 - yS) > TOL:
        fail("slider_crank", f"two rails either side of y = e ({yS}) expected, drawn at {ys}")


def check_quick_return(d, row):
    r, dd, L = 0.75, 1.5, 4.0  # models/quick_return.yaml
    t1, t4 = row["theta_crank"], row["theta_rocker"]
    A = (r * math.cos(t1), dd + r * math.sin(t1))
    O4, O2 = (0.0, 0.0), (0.0, dd)
    Bq = (L * math.cos(t4), L * math.sin(t4))
    check_binary("quick_return", d, "crank", O2, A)
    check_binary("quick_return", d, "rocker", O4, Bq)
    blk = block_of(d, "block")
    if blk is None or not near(blk[0], d.px(A)) or not parallel(blk[1], t4):
        fail("quick_return", f"the block should sit on A {d.px(A)} along the rocker, drawn: {blk}")
    # The slot: a 4-corner outline in the rocker along its line.
    slots = [p for p in polygons(d, "rocker", "link") if len(p) == 4]
    if len(slots) != 1:
        fail("quick_return", f"one slot in the rocker expected, drawn: {slots}")
    apexes = pivot_apexes(d)
    if not same_points(apexes, [d.px(O4), d.px(O2)]):
        fail("quick_return", f"ground pivots at O4 and O2 only (R guides the ram), drawn at {apexes}")


def check_planetary(d, row):
    rs, rp, rr = 1.0, 0.5, 2.0  # models/planetary.yaml
    ta = row["theta_arm"]
    P = ((rs + rp) * math.cos(ta), (rs + rp) * math.sin(ta))
    want = {"sun": [((0.0, 0.0), rs)], "planet": [(P, rp), (P, rp)]}
    for link, items in want.items():
        got = circles(d, link)
        for c, radius in items:
            if not any(near(g[0], d.px(c)) and abs(g[1] - radius * d.scale) < TOL for g in got):
                fail("planetary", f"{link}: pitch circle r {radius * d.scale} at {d.px(c)} expected, drawn: {got}")
    ring = [e for e in d.group("ground").iter(NS + "circle")
            if abs(float(e.get("r")) - rr * d.scale) < TOL]
    if not ring:
        fail("planetary", "the ring's pitch circle (ground) is missing")


def check_cam_roller(d, row):
    e, rr = 0.3, 0.25  # models/cam_roller.yaml
    C = (e, row["s_slide"])
    got = circles(d, "follower")
    if not any(near(g[0], d.px(C)) and abs(g[1] - rr * d.scale) < TOL for g in got):
        fail("cam_roller", f"roller r {rr * d.scale} at {d.px(C)} expected, drawn: {got}")
    # The profile touches the roller: its nearest point is rr from C.
    prof = [p for p in polygons(d, "cam") if len(p) > 40]
    if len(prof) != 1:
        fail("cam_roller", "one cam profile expected")
    else:
        c = d.px(C)
        dist = min(math.hypot(p[0] - c[0], p[1] - c[1]) for p in prof[0])
        if abs(dist - rr * d.scale) > 0.02 * rr * d.scale + 1.0:
            fail("cam_roller", f"the profile should touch the roller: nearest {dist} px, roller {rr * d.scale} px")


CHECKS = {"fourbar": check_fourbar, "slider_crank": check_slider_crank, "quick_return": check_quick_return,
          "planetary": check_planetary, "cam_roller": check_cam_roller}


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    return struct.unpack(">II", head[16:24])


def main():
    rsvg = sys.argv[2]
    view = sys.argv[3]
    objects = sys.argv[4:]
    checked = set()
    with tempfile.TemporaryDirectory() as tmp:
        for obj in objects:
            model = os.path.splitext(os.path.basename(obj))[0]
            svg, csv_path, png = (os.path.join(tmp, model + ext) for ext in (".svg", ".csv", ".png"))
            r = subprocess.run([view, "sweep", obj, "--steps", "120", "--svg", svg, "--csv", csv_path, "--table", "0"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, timeout=300)
            if r.returncode not in (0, 3) or not os.path.exists(svg):
                fail(model, f"sweep exit status {r.returncode}: {r.stderr.strip()}")
                continue
            try:
                root = ET.parse(svg).getroot()
            except ET.ParseError as err:
                fail(model, f"not well-formed: {err}")
                continue
            for c in root.iter(NS + "circle"):
                if c.get("cx") is None or c.get("cy") is None or c.get("r") is None:
                    fail(model, "a <circle> without cx, cy or r")
                    break
            d = Drawing(root)
            mech = d.group("mechanism")
            if mech is None or not mech.findall(NS + "g"):
                fail(model, "the mechanism is not drawn")
                continue
            width, height = int(root.get("width")), int(root.get("height"))
            if rsvg:
                r = subprocess.run([rsvg, "-o", png, svg], stderr=subprocess.PIPE, text=True, timeout=120)
                size = png_size(png) if r.returncode == 0 and os.path.exists(png) else None
                if size != (width, height) or os.path.getsize(png) < 2000:
                    fail(model, f"rsvg-convert: status {r.returncode} {r.stderr.strip()}, PNG size {size}, "
                                f"expected {(width, height)}")
            if model in CHECKS:
                CHECKS[model](d, first_row(csv_path))
                checked.add(model)
    missing = set(CHECKS) - checked
    if missing:
        fail("test", f"models with geometry checks not run: {sorted(missing)}")
    print(f"{len(objects)} models drawn, geometry checked on {len(checked)}, {len(failures)} failure(s)"
          + ("" if rsvg else "; rsvg-convert not found: PNG rendering not checked"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
