#!/usr/bin/env python3
"""Measures the parts of a hand-drawn sketch from its strokes, for tests/shared_parts.rs.

The references in tests/shared_scripts/parts/NAME.reference.json describe the DRAWING,
not geosnap's snapper: each part names the strokes (or stroke ends) that draw it, read off
a labelled drawing, and this script turns those strokes into 2D measurements in sketch
space (SVG viewBox units, y down). Nothing here calls the snapper.

    cargo run --release --no-default-features --example dump_strokes -- S.svg > S.json
    tools/measure_parts.py draw S.json S.png [REF.json|- [X0,Y0,X1,Y1]]
        # strokes in colours, labelled by id (needs Pillow), with the references
    tools/measure_parts.py measure S.json NAME.reference.json   # fills in every part

A stroke reference is an id (all its points), "ID:start" / "ID:end" (one end point),
"ID:A-B" (the stretch from fraction A to B of its arc length), "ID@y=V" / "ID@x=V" (the
first point where the stroke crosses that level: where a part's outline runs on into the
next part's, at the level where the drawn outline changes course) or "ID@x<V" (and
"@x>", "@y<", "@y>": the stretch of the stroke on that side of the level, cut at it: one
stroke drawing two parts, such as a menorah's two arms meeting at the stem's axis). Each part's "measure":

- {"ends": [REFS, REFS]} (cylinder, cone, SGC): the strokes drawing each end (its
  ellipse, or the silhouette ends that meet there when the end is hidden). With the
  axis through the two end centres, an end's ellipse has its major axis across the axis
  (orthographic view of a circle), so its end points are the extreme points across the
  axis: the centre is their midpoint and the radius half their spread. Iterated from the
  strokes' centroids until the axis settles.
- {"sphere": REFS}: an algebraic least-squares circle (Kasa) through the outline strokes.
- {"corners": [REFS, ...]}: a box's outline polygon, one corner per entry, each the mean of
  the given points (usually the end points of the edges that meet there), in order around
  the outline.
- {"sides": [REFS, REFS]} (bent tube): its two silhouettes, each a chain of strokes in
  order. Both are resampled at 64 equal arc-length fractions from the same end; the spine
  is the midline of corresponding samples and the radius the median of half the distance
  from one side's samples to the other side.
"""
import json
import math
import sys


def load_strokes(path):
    with open(path) as f:
        sketch = json.load(f)
    return {s["id"]: [tuple(p) for p in s["points"]] for s in sketch["strokes"]}, sketch


def arclen(points):
    acc = [0.0]
    for a, b in zip(points, points[1:]):
        acc.append(acc[-1] + math.dist(a, b))
    return acc


def at_fraction(points, t):
    acc = arclen(points)
    total = acc[-1]
    if total == 0:
        return points[0]
    target = t * total
    for i in range(1, len(points)):
        if acc[i] >= target:
            seg = acc[i] - acc[i - 1]
            u = 0 if seg == 0 else (target - acc[i - 1]) / seg
            a, b = points[i - 1], points[i]
            return (a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]))
    return points[-1]


def resolve(strokes, ref):
    """The points of one stroke reference."""
    if isinstance(ref, int):
        return list(strokes[ref])
    if "@x<" in ref or "@x>" in ref or "@y<" in ref or "@y>" in ref:
        sid, _, cond = ref.partition("@")
        k = 0 if cond[0] == "x" else 1
        v = float(cond[2:])
        keep = (lambda p: p[k] < v) if cond[1] == "<" else (lambda p: p[k] > v)
        pts = strokes[int(sid)]
        out = []
        for a, b in zip(pts, pts[1:]):
            if keep(a):
                out.append(a)
            if keep(a) != keep(b) and a[k] != b[k]:
                u = (v - a[k]) / (b[k] - a[k])
                out.append((a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])))
        if keep(pts[-1]):
            out.append(pts[-1])
        return out
    if "@" in ref:
        sid, _, cond = ref.partition("@")
        axis, _, value = cond.partition("=")
        k = 0 if axis == "x" else 1
        v = float(value)
        pts = strokes[int(sid)]
        for a, b in zip(pts, pts[1:]):
            if (a[k] - v) * (b[k] - v) <= 0 and a[k] != b[k]:
                u = (v - a[k]) / (b[k] - a[k])
                return [(a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]))]
        raise ValueError("stroke %s never reaches %s" % (sid, cond))
    sid, _, part = ref.partition(":")
    pts = strokes[int(sid)]
    if part == "start":
        return [pts[0]]
    if part == "end":
        return [pts[-1]]
    a, b = (float(x) for x in part.split("-"))
    n = max(8, int(len(pts) * abs(b - a)) + 2)
    return [at_fraction(pts, a + (b - a) * k / (n - 1)) for k in range(n)]


def ids_of(refs):
    out = []
    for r in refs:
        i = r if isinstance(r, int) else int(r.partition(":")[0].partition("@")[0])
        if i not in out:
            out.append(i)
    return out


def mean(points):
    n = len(points)
    return (sum(p[0] for p in points) / n, sum(p[1] for p in points) / n)


def measure_ends(strokes, ends):
    groups = [[p for r in refs for p in resolve(strokes, r)] for refs in ends]
    centres = [mean(g) for g in groups]
    radii = [0.0, 0.0]
    for _ in range(10):
        ax = (centres[1][0] - centres[0][0], centres[1][1] - centres[0][1])
        n = math.hypot(*ax)
        if n == 0:
            perp = (1.0, 0.0)
        else:
            perp = (-ax[1] / n, ax[0] / n)
        new = []
        for k, g in enumerate(groups):
            proj = [p[0] * perp[0] + p[1] * perp[1] for p in g]
            lo = g[proj.index(min(proj))]
            hi = g[proj.index(max(proj))]
            new.append(((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2))
            radii[k] = (max(proj) - min(proj)) / 2
        centres = new
    return [{"center": [round(c[0], 1), round(c[1], 1)], "radius": round(r, 1)}
            for c, r in zip(centres, radii)]


def solve(m, v):
    """Gaussian elimination with partial pivoting."""
    n = len(v)
    a = [row[:] + [v[i]] for i, row in enumerate(m)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(a[r][c]))
        a[c], a[p] = a[p], a[c]
        for r in range(n):
            if r != c:
                f = a[r][c] / a[c][c]
                for k in range(c, n + 1):
                    a[r][k] -= f * a[c][k]
    return [a[i][n] / a[i][i] for i in range(n)]


def measure_sphere(strokes, refs):
    pts = [p for r in refs for p in resolve(strokes, r)]
    # x² + y² + D x + E y + F = 0, least squares.
    m = [[0.0] * 3 for _ in range(3)]
    v = [0.0] * 3
    for x, y in pts:
        row = (x, y, 1.0)
        rhs = -(x * x + y * y)
        for i in range(3):
            v[i] += row[i] * rhs
            for j in range(3):
                m[i][j] += row[i] * row[j]
    d, e, f = solve(m, v)
    cx, cy = -d / 2, -e / 2
    r = math.sqrt(cx * cx + cy * cy - f)
    return {"center": [round(cx, 1), round(cy, 1)], "radius": round(r, 1)}


def measure_corners(strokes, corners):
    out = []
    for refs in corners:
        c = mean([p for r in refs for p in resolve(strokes, r)])
        out.append([round(c[0], 1), round(c[1], 1)])
    return {"outline": out}


def chain(strokes, refs):
    """The points of strokes drawn one after another, each turned to follow the last."""
    pts = []
    for i, r in enumerate(refs):
        seg = resolve(strokes, r)
        if pts:
            if math.dist(pts[-1], seg[-1]) < math.dist(pts[-1], seg[0]):
                seg = seg[::-1]
        elif len(refs) > 1:
            nxt = resolve(strokes, refs[1])
            ends = [nxt[0], nxt[-1]]
            if min(math.dist(seg[0], e) for e in ends) < min(math.dist(seg[-1], e) for e in ends):
                seg = seg[::-1]
        pts.extend(seg)
    return pts


def closest_on(poly, p):
    best = float("inf")
    for a, b in zip(poly, poly[1:]):
        dx, dy = b[0] - a[0], b[1] - a[1]
        l2 = dx * dx + dy * dy
        u = 0 if l2 == 0 else max(0, min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2))
        q = (a[0] + u * dx, a[1] + u * dy)
        best = min(best, math.dist(p, q))
    return best


def measure_sides(strokes, sides):
    a = chain(strokes, sides[0])
    b = chain(strokes, sides[1])
    if math.dist(a[0], b[-1]) + math.dist(a[-1], b[0]) < math.dist(a[0], b[0]) + math.dist(a[-1], b[-1]):
        b = b[::-1]
    n = 64
    sa = [at_fraction(a, k / (n - 1)) for k in range(n)]
    sb = [at_fraction(b, k / (n - 1)) for k in range(n)]
    spine = [[round((p[0] + q[0]) / 2, 1), round((p[1] + q[1]) / 2, 1)] for p, q in zip(sa, sb)]
    half = sorted([closest_on(b, p) / 2 for p in sa] + [closest_on(a, q) / 2 for q in sb])
    radius = half[len(half) // 2]
    # Keep every fourth sample (and the last): a polyline to compare against.
    spine = spine[::4] + ([spine[-1]] if (n - 1) % 4 else [])
    return {"spine": spine, "radius": round(radius, 1)}


def measure(strokes_path, ref_path):
    strokes, _ = load_strokes(strokes_path)
    with open(ref_path) as f:
        ref = json.load(f)
    for part in ref["parts"]:
        m = part["measure"]
        refs = []
        for k in ("ends", "sphere", "corners", "sides"):
            if k in m:
                v = m[k]
                if k == "sphere":
                    part["sphere"] = measure_sphere(strokes, v)
                    refs += v
                elif k == "ends":
                    part["ends"] = measure_ends(strokes, v)
                    refs += [r for g in v for r in g]
                elif k == "corners":
                    part["box"] = measure_corners(strokes, v)
                    refs += [r for g in v for r in g]
                else:
                    part["tube"] = measure_sides(strokes, v)
                    refs += [r for g in v for r in g]
        part["strokes"] = sorted(ids_of(refs))
    text = json.dumps(ref, indent=1)
    with open(ref_path, "w") as f:
        f.write(text + "\n")


PALETTE = [(220, 0, 0), (0, 0, 230), (0, 140, 0), (200, 0, 200), (240, 140, 0),
           (0, 150, 150), (120, 0, 180), (140, 80, 20), (110, 110, 0), (0, 0, 120)]


def draw(strokes_path, png, ref_path=None, crop=None):
    """A PNG of the strokes in colours, each labelled with its id (a dot marks its start),
    with the measured references in black when a reference file is given. Needs Pillow."""
    from PIL import Image, ImageDraw, ImageFont

    strokes, _ = load_strokes(strokes_path)
    xs = [p[0] for s in strokes.values() for p in s]
    ys = [p[1] for s in strokes.values() for p in s]
    x0, y0, x1, y1 = min(xs), min(ys), max(xs), max(ys)
    if crop:
        x0, y0, x1, y1 = crop
    scale = 1400 / max(x1 - x0, y1 - y0)
    w, h = int((x1 - x0) * scale) + 80, int((y1 - y0) * scale) + 80
    img = Image.new("RGB", (w, h), "white")
    d = ImageDraw.Draw(img)
    try:
        font = ImageFont.load_default(size=18)
    except TypeError:
        font = ImageFont.load_default()

    def tr(p):
        return ((p[0] - x0) * scale + 40, (p[1] - y0) * scale + 40)

    for k, (sid, pts) in enumerate(sorted(strokes.items())):
        col = PALETTE[k % len(PALETTE)]
        d.line([tr(p) for p in pts], fill=col, width=2)
        sx, sy = tr(pts[0])
        d.ellipse([sx - 4, sy - 4, sx + 4, sy + 4], fill=col)
        mx, my = tr(pts[len(pts) // 2])
        d.text((mx + 3, my - 18), str(sid), fill=col, font=font)
    if ref_path:
        with open(ref_path) as f:
            ref = json.load(f)
        for i, part in enumerate(ref["parts"]):
            label = None
            for e in part.get("ends", []):
                cx, cy = tr(e["center"])
                r = e["radius"] * scale
                d.ellipse([cx - r, cy - r, cx + r, cy + r], outline="black")
                d.ellipse([cx - 3, cy - 3, cx + 3, cy + 3], fill="black")
                label = (cx, cy)
            if "sphere" in part:
                cx, cy = tr(part["sphere"]["center"])
                r = part["sphere"]["radius"] * scale
                d.ellipse([cx - r, cy - r, cx + r, cy + r], outline="black")
                label = (cx, cy)
            if "box" in part:
                poly = [tr(p) for p in part["box"]["outline"]]
                d.line(poly + [poly[0]], fill="black", width=1)
                label = poly[0]
            if "tube" in part:
                poly = [tr(p) for p in part["tube"]["spine"]]
                d.line(poly, fill="black", width=1)
                label = poly[len(poly) // 2]
            if label:
                d.text((label[0] + 5, label[1] + 2), "#%d" % i, fill="black", font=font)
    img.save(png)


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "draw":
        crop = [float(v) for v in sys.argv[5].split(",")] if len(sys.argv) > 5 else None
        draw(sys.argv[2], sys.argv[3], sys.argv[4] if len(sys.argv) > 4 and sys.argv[4] != "-" else None, crop)
    elif len(sys.argv) == 4 and sys.argv[1] == "measure":
        measure(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
