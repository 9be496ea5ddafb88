#!/usr/bin/env python3
"""An open sheet (a piece of the unit sphere, 12 x 8 quads) with semi-sharp creases along grid
lines that run into its boundary: the feature class of a held-back OpenSubdiv shape of issue 46
(semi-sharp creases of sharpness 7 meeting the boundary, valence-2 boundary corners, which the
edge-and-corner rule makes corners). Writes an OBJ with OpenSubdiv's tags.

  tools/feature_meshes/creased_sheet.py --sharpness 7 --boundary edge-and-corner -o sheet.obj
"""
import argparse
import math


def sheet(nx=12, ny=8):
    index, points = {}, []
    for j in range(ny + 1):
        for i in range(nx + 1):
            theta, phi = (i / nx - 0.5) * 2.2, (j / ny - 0.5) * 1.6
            index[i, j] = len(points)
            points.append((math.sin(theta) * math.cos(phi), math.sin(phi), math.cos(theta) * math.cos(phi)))
    faces = [(index[i, j], index[i + 1, j], index[i + 1, j + 1], index[i, j + 1]) for j in range(ny) for i in range(nx)]
    # Three lines across v and one across u, each from boundary to boundary: 36 crease edges.
    creases = [(index[i, j], index[i, j + 1]) for i in (3, 6, 9) for j in range(ny)]
    creases += [(index[i, ny // 2], index[i + 1, ny // 2]) for i in range(nx)]
    return points, faces, creases


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sharpness", type=float, default=7.0)
    parser.add_argument("--boundary", choices=["edge-and-corner", "edge-only"], default="edge-and-corner")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()
    points, faces, creases = sheet()
    with open(args.output, "w") as out:
        for p in points:
            out.write("v %.6f %.6f %.6f\n" % p)
        for f in faces:
            out.write("f %s\n" % " ".join(str(v + 1) for v in f))
        out.write("t interpolateboundary 1/0/0 %d\n" % (1 if args.boundary == "edge-and-corner" else 2))
        if args.sharpness > 0:
            for a, b in creases:
                out.write("t crease 2/1/0 %d %d %g\n" % (a, b, args.sharpness))


if __name__ == "__main__":
    main()
