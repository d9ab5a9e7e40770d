#!/usr/bin/env python3
"""Writes a photo annotation (sheetform's JSON) as an SVG drawing over the photo, in the
layer convention `sheetform photo` reads (docs/guide/photo.md, "Tracing in Inkscape"): open it in
Inkscape, edit the curves, and run `sheetform photo drawing.svg -o OUT`.

    python3 tools/annotation_to_svg.py examples/photo/coffee-cup.json > examples/photo/coffee-cup.svg

The SVG links the photo by the annotation's relative path, so write it next to the JSON.
Standard library only.
"""
import json
import sys
from xml.sax.saxutils import quoteattr


def path_data(points, closed):
    d = "M {:.6f},{:.6f}".format(*points[0])
    for k in range(1, len(points), 3):
        a, b, c = points[k:k + 3]
        d += " C {:.6f},{:.6f} {:.6f},{:.6f} {:.6f},{:.6f}".format(*a, *b, *c)
    return d + (" Z" if closed else "")


def main():
    annotation = json.load(open(sys.argv[1]))
    w, h = annotation["image"]["width"], annotation["image"]["height"]
    mirror = {}
    for a, b in annotation.get("symmetric_curves", []):
        mirror[a] = b
    selfsym = set(annotation.get("self_symmetric_curves", []))
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
        'xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" '
        f'width="{w}" height="{h}" viewBox="0 0 {w} {h}">',
        f"<title>{annotation.get('name', 'photo')}</title>",
        '<g inkscape:groupmode="layer" inkscape:label="photo">',
        f'<image x="0" y="0" width="{w}" height="{h}" xlink:href={quoteattr(annotation["image"]["path"])}/>',
        "</g>",
    ]
    for kind, layer, colour in (("silhouette", "silhouettes", "#ff7f00"), ("boundary", "boundaries", "#2b83ba")):
        out.append(f'<g inkscape:groupmode="layer" inkscape:label="{layer}" style="fill:none;stroke:{colour};stroke-width:2">')
        for c in annotation["curves"]:
            if c["kind"] != kind:
                continue
            label = c["name"]
            if c["name"] in mirror:
                label += " | mirror " + mirror[c["name"]]
            if c["name"] in selfsym:
                label += " | self-symmetric"
            d = path_data(c["control_points"], c.get("closed", False))
            out.append(f'<path inkscape:label={quoteattr(label)} d="{d}"/>')
        out.append("</g>")
    s = annotation["symmetry"]
    out.append('<g inkscape:groupmode="layer" inkscape:label="symmetry" style="fill:none;stroke:#00bcd4;stroke-width:2">')
    for seg in s["frame"]:
        out.append('<path inkscape:label="frame" d="M {},{} L {},{}"/>'.format(*seg[0], *seg[1]))
    label = "pair flip" if s.get("flip_depth") else "pair"
    out.append(f'<path inkscape:label="{label}" style="stroke:#e41a1c" d="M {s["points"][0][0]},{s["points"][0][1]} L {s["points"][1][0]},{s["points"][1][1]}"/>')
    out.append("</g>")
    out.append('<g inkscape:groupmode="layer" inkscape:label="marks" style="fill:none;stroke:#984ea3;stroke-width:2">')
    for p in annotation.get("openings", []):
        out.append(f'<circle inkscape:label="opening" cx="{p[0]}" cy="{p[1]}" r="4"/>')
    for p in annotation.get("occlusions", []):
        out.append(f'<circle inkscape:label="occlusion" cx="{p[0]}" cy="{p[1]}" r="4"/>')
    t = annotation["true_size"]
    unit = annotation.get("units", "mm")
    out.append(f'<path inkscape:label="true-size {t["length"]} {unit}" d="M {t["from"][0]},{t["from"][1]} L {t["to"][0]},{t["to"][1]}"/>')
    out.append("</g>")
    out.append("</svg>")
    print("\n".join(out))


if __name__ == "__main__":
    main()
