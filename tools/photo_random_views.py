"""Random views of exact developables for the photo property tests (issue 37).

    python3 tools/photo_random_views.py SEED COUNT DIR [--noise SIGMA [--exact-marks]]

Writes COUNT annotations `view-NN.json` and their ground truth `view-NN.truth.json` to
DIR, made by `tools/make_photo_examples.py` (same conventions, same truth format) from
random models and cameras drawn with `random.Random(SEED)`:

- the model: an open cylinder (radius 50-100 px, height 100-200 px), a truncated cone
  (radii 40-100 px, at least 15 px apart, widening up or down, height 100-180 px) or a
  cylinder on a cone (neck 60-90 px high, cone 70-120 px high, bottom radius 40-75 % of
  the neck's);
- the camera: elevation 15-50 deg, any azimuth, an image roll of -15..15 deg, the
  symmetry plane 30-60 deg from the plane seen edge-on (either side), orthographic or
  perspective (horizontal field of view 35-65 deg), half each;
- with `--noise SIGMA`: the orthographic views get the examples' annotation noise
  (`add_noise`: nodes moved by N(0, SIGMA^2) px, C1 joins kept), SIGMA in px; with
  `--exact-marks` as well, on the curves only (the symmetry marks and the true size as
  drawn without noise).

A view the generator cannot draw (a silhouette that does not exist from that camera) is
drawn again; the seeds are fixed, so the same command writes the same files. No PNG is
rendered (the reconstruction does not read the photo). Standard library only.
"""

import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_photo_examples as mpe  # noqa: E402


def random_spec(rng, k):
    kind = rng.choice(["cylinder", "cone", "composite"])
    if kind == "cylinder":
        r, h = rng.uniform(50, 100), rng.uniform(100, 200)
        rings, patches = [("bottom", 0.0, r), ("top", h, r)], [("tube", 0, 1)]
    elif kind == "cone":
        a = rng.uniform(55, 100)
        b = rng.uniform(40, a - 15)
        if rng.random() < 0.5:
            a, b = b, a
        h = rng.uniform(100, 180)
        rings, patches = [("bottom", 0.0, a), ("top", h, b)], [("cone", 0, 1)]
    else:
        r = rng.uniform(60, 90)
        cone_h, neck_h = rng.uniform(70, 120), rng.uniform(60, 90)
        bottom = r * rng.uniform(0.4, 0.75)
        rings = [("bottom", 0.0, bottom), ("joint", cone_h, r), ("top", cone_h + neck_h, r)]
        patches = [("cone", 0, 1), ("neck", 1, 2)]
    return {
        "name": f"view-{k:02}",
        "title": f"random view {k} ({kind})",
        "seed": rng.randrange(1, 10**9),
        "roll": math.radians(rng.uniform(-15, 15)),
        "rings": rings,
        "patches": patches,
        "kind": kind,
    }


def set_camera(rng):
    elevation = rng.uniform(15, 50)
    azimuth = rng.uniform(0, 360)
    mpe.ELEVATION_DEG, mpe.AZIMUTH_DEG = elevation, azimuth
    mpe.ELEVATION, mpe.AZIMUTH = math.radians(elevation), math.radians(azimuth)
    mpe.BASE = mpe.AZIMUTH - math.pi  # (angles kept in [BASE, BASE + 2 pi): the front never wraps)
    mpe.PHI = mpe.AZIMUTH + rng.choice([-1, 1]) * math.radians(rng.uniform(30, 60))
    mpe.FOV = math.radians(rng.uniform(35, 65))
    mpe.FOCAL = (mpe.IMG_W / 2) / math.tan(mpe.FOV / 2)
    return "perspective" if rng.random() < 0.5 else "ortho"


def main(argv):
    seed, count, out = int(argv[0]), int(argv[1]), argv[2]
    noise = float(argv[argv.index("--noise") + 1]) if "--noise" in argv else None
    rng = random.Random(seed)
    os.makedirs(out, exist_ok=True)
    k = 0
    attempts = 0
    while k < count:
        attempts += 1
        if attempts > 20 * count:
            raise SystemExit("too many views could not be drawn")
        spec = random_spec(rng, k)
        variant = set_camera(rng)
        if noise is not None:
            variant, mpe.NOISE_SIGMA = "noisy", noise
        try:
            name, _, ann, truth, _ = mpe.build(spec, variant)
            if noise is not None and "--exact-marks" in argv:
                # The noise on the curves only: the symmetry marks and the true size
                # of the noise-free drawing.
                _, _, exact, _, _ = mpe.build(spec, "ortho")
                ann["symmetry"], ann["true_size"] = exact["symmetry"], exact["true_size"]
        except (ValueError, ZeroDivisionError, IndexError, TypeError):
            continue
        name = spec["name"]
        ann["name"] = spec["title"]
        truth["annotation"] = name + ".json"
        truth["model_kind"] = spec["kind"]
        truth["variant"] = variant
        for stem, data in ((name, ann), (name + ".truth", truth)):
            with open(os.path.join(out, stem + ".json"), "w") as f:
                json.dump(data, f, indent=1)
                f.write("\n")
        k += 1


if __name__ == "__main__":
    main(sys.argv[1:])
