#!/usr/bin/env python3
"""Nimbus against Mitsuba 3 on the same clouds, in one command.

1. `nimbus export-density SCENE --mitsuba scene.xml` exports the scene's density (each voxel the
   average over it) and the Mitsuba scene around it: the grid in place, the genus' phase
   function tabulated from the model, the sun (irradiance 1), the camera.
2. `nimbus render SCENE --verification --format exr` renders the same view in verification mode:
   pure single scattering of a sun of irradiance 1 (no sky light, powder, ground bounce, haze,
   aerial perspective or background), linear.
3. Mitsuba renders single scattering (volpath, max_depth 2) and, with the sun off, a uniform sky
   of radiance 1 and albedo 0, the clouds' transmittance.
4. The two are compared over the pixels that see cloud: the image-mean difference (the bias the
   goal of 0.5 % is about), and the mean and 95th percentile of the per-pixel difference, all
   against Mitsuba's first render. Mitsuba renders a second time with another seed: the
   difference of the two renders carries two renders' noise, so divided by sqrt(2) it is one
   render's noise, the floor Nimbus-vs-Mitsuba (which carries Mitsuba's noise once) is measured
   against. Agreement means Nimbus is as close to Mitsuba as one Mitsuba render is to the truth.
   The bar for a mean (the image's, the thin edges') is the standard error of one render's
   mean, from the two renders' per-pixel differences (`mean_noise`): the difference of the two
   means is a single draw of that noise and can come out near zero by chance.
   A view with no cloud is refused before Mitsuba renders (nothing to agree on): at the export
   when the grid holds none, else by Nimbus's transmittance.

    pip install -r tools/requirements.txt
    cargo build --release -p nimbus-cli
    python3 tools/mitsuba_agreement.py            # the README's table, about 4 minutes

With --multiple-scattering it also renders Nimbus's two multiple-scattering models, the
diffusion (`--enable diffusion`, the presets' model) and the octaves (`--octaves 8`, the older
one), in verification mode otherwise, against Mitsuba's full volumetric path tracer on the same
grid, and reports each one's ratio of mean radiance. The grid is then widened by --margin layer
depths on every side (2 by default): light scattered many times reaches the viewed clouds from
a few layer depths away, and a box that ends sooner lets it leak out of its sides (a deck seen
from below read 1.45 times darker in Mitsuba with no margin than with 2).
"""
import argparse
import copy
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import OpenEXR

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(cmd):
    print("$ " + " ".join(cmd), flush=True)
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.stderr.write(out.stdout + out.stderr)
        raise SystemExit(f"failed: {' '.join(cmd)}")
    return out.stdout + out.stderr


def read_exr(path):
    with OpenEXR.File(path, separate_channels=True) as f:
        ch = f.channels()
        return {name: np.asarray(c.pixels, dtype=np.float64) for name, c in ch.items()}


def mitsuba_render(mi, xml, width, height, spp, seed, **params):
    scene = mi.load_file(xml, width=width, height=height, spp=spp, **params)
    return np.asarray(mi.render(scene, seed=seed), dtype=np.float64)


def compare(a, b, mask):
    """Differences of image a against b over the masked pixels, relative to b's mean there."""
    ref = b[mask].mean()
    d = a[mask] - b[mask]
    return {
        "mean_signed": float(d.mean() / ref),
        "mean_abs": float(np.abs(d).mean() / ref),
        "p95_abs": float(np.percentile(np.abs(d), 95) / ref),
    }


def absolute(a, b, mask):
    """Absolute differences of a against b over the masked pixels (for fractions)."""
    d = a[mask] - b[mask]
    return {
        "mean_signed": float(d.mean()),
        "mean_abs": float(np.abs(d).mean()),
        "p95_abs": float(np.percentile(np.abs(d), 95)),
    }


def mean_noise(m0, m1, mask):
    """The noise of one Mitsuba render's mean over the masked pixels, relative to that mean:
    the standard error from the pixels' own scatter. Two renders differ per pixel by noise of
    variance 2σ², so σ = std(m1 − m0)/√2, and a mean over N independent pixels carries σ/√N.
    (The difference of the two renders' means is one draw of that noise, and can come out near
    zero by chance: a bar from it alone is not a fair one.)"""
    d = (m1 - m0)[mask]
    if d.size < 2:
        return float("nan")
    return float(d.std(ddof=1) / np.sqrt(2.0 * d.size) / abs(m0[mask].mean()))


def one_render(pair):
    """The figures of the difference of two independent renders, scaled to one render's noise:
    the difference of two renders of equal noise has sqrt(2) times the noise of either."""
    return {k: v / np.sqrt(2.0) for k, v in pair.items()}


# Transmittance from which a cloudy pixel counts as a thin edge.
THIN_EDGE = 0.9


def thin_edges(nimbus_l, mit_l, edge):
    """Single scattering over the thin edges: Nimbus's image mean there against Mitsuba's first
    render, and one Mitsuba render's noise on that mean (None when the view has no such pixel)."""
    pixels = int(edge.sum())
    if pixels == 0:
        return {"pixels": 0}
    return {
        "pixels": pixels,
        "nimbus_vs_mitsuba": compare(nimbus_l, mit_l[0], edge)["mean_signed"],
        "noise_floor": mean_noise(mit_l[0], mit_l[1], edge),
    }


def edge_cell(e):
    if e["pixels"] == 0:
        return "— (none)"
    return f"{pct(e['nimbus_vs_mitsuba'])} ± {100 * e['noise_floor']:.2f} % ({e['pixels']} px)"


def refuse(message):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(2)


def pct(x):
    return f"{100 * x:+.2f} %" if x < 0 else f"{100 * x:.2f} %"


# Voxel edge (m) of the exported grid, unless a view or --voxel says otherwise.
VOXEL = 13.0

# The agreement suite: each view of examples/verification/, with what its export needs (the
# box the default region spans within `--reach` of the camera, and the voxel). The cumulus
# views' thin edges need fine voxels: the grid's interpolation spreads the faint margin of a
# cloud over a voxel, and on 13 m voxels that margin was 6 % more opaque than the model's own
# density marched in 1 m steps (1.3 % on 6.5 m voxels), a bias of the reference, not of Nimbus.
# Each takes the finest voxel its box allows within the exporter's 1,024 per axis (the low
# sun's box is 5.5 km across). The low sun's thin edges take 2,048 samples per pixel: at 512
# one render's mean over them is ±1.5 % (a first render 1.8 % low read as a +2.2 % bias).
SUITE = [
    ("cumulus-nadir.toml", {"voxel": 3.25}),
    ("cumulus-low-sun.toml", {"voxel": 5.5, "spp": 2048}),
    ("deck-above.toml", {}),
    ("deck-below.toml", {}),
    ("thin-high.toml", {}),
    ("inside-cloud.toml", {"reach": 3000.0}),
]


def parser():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--nimbus", default=os.path.join(ROOT, "target/release/nimbus"))
    p.add_argument("--scene", default=os.path.join(ROOT, "examples/verification/cumulus-nadir.toml"))
    p.add_argument("--suite", action="store_true",
                   help="every view of examples/verification/ (SUITE), one summary table")
    p.add_argument("--resolution", default="96x54")
    p.add_argument("--voxel", type=float, default=None,
                   help=f"voxel edge (m; default {VOXEL}, or the suite view's own); the shape texel is 52 m")
    p.add_argument("--reach", type=float, default=None, help="export-density --reach (m)")
    p.add_argument("--filter", type=int, default=2, help="samples per axis averaged per voxel")
    p.add_argument("--spp", type=int, default=1024, help="Mitsuba samples per pixel")
    p.add_argument("--ms-spp", type=int, default=None,
                   help="Mitsuba samples per pixel of the full path tracer (default: --spp)")
    p.add_argument("--frames", type=int, default=16, help="Nimbus accumulated frames")
    p.add_argument("--variant", default="scalar_rgb")
    p.add_argument("--multiple-scattering", action="store_true")
    p.add_argument("--margin", type=float, default=2.0,
                   help="with --multiple-scattering: export-density --margin, in layer depths")
    p.add_argument("--sun-scale", type=float, default=1.0,
                   help="scale Mitsuba's sun by this (a control: 0.9 must show Nimbus 11 %% brighter)")
    p.add_argument("--out", default=None, help="folder for the renders and agreement.json")
    return p


def main():
    a = parser().parse_args()

    import mitsuba as mi

    mi.set_variant(a.variant)
    work = a.out or tempfile.mkdtemp(prefix="nimbus-agreement-")
    os.makedirs(work, exist_ok=True)
    if not a.suite:
        report = agree(a, mi, a.scene, a.reach, work, a.voxel or VOXEL)
        print_report(report, work)
        return 0
    reports = []
    for name, options in SUITE:
        view_work = os.path.join(work, name[: -len(".toml")])
        os.makedirs(view_work, exist_ok=True)
        scene = os.path.join(ROOT, "examples/verification", name)
        # With --multiple-scattering the box widens by --margin layer depths on every side,
        # and the cumulus views' 6.5 m grid would need more than 1,024 voxels a side: those
        # take the default voxel there (their thin edges then carry the 13 m grid's bias).
        voxel = VOXEL if a.multiple_scattering else options.get("voxel", VOXEL)
        # A view may ask for more of Mitsuba's single-scattering samples than --spp gives.
        # (The full path tracer keeps its own count.)
        view_args = copy.copy(a)
        view_args.ms_spp = a.ms_spp or a.spp
        view_args.spp = max(a.spp, options.get("spp", 0))
        reports.append(agree(view_args, mi, scene, options.get("reach", a.reach), view_work,
                             a.voxel or voxel))
        print_report(reports[-1], view_work)
    with open(os.path.join(work, "suite.json"), "w") as f:
        json.dump(reports, f, indent=2)
    print_suite(reports, a)
    return 0


def print_suite(reports, a):
    """One row per view: single scattering against one Mitsuba render's noise, transmittance,
    and (with --multiple-scattering) the ratio of mean radiance to Mitsuba's path tracer."""
    print()
    print(f"agreement suite: {a.resolution}, Mitsuba {a.spp} spp x 2 seeds, Nimbus {a.frames} frames")
    print()
    print("| view | cloudy px | single, image mean | floor | single, per pixel mean / floor | "
          "transmittance, mean abs / floor | thin edges (T ≥ 0.9), single, mean ± floor | multiple, diffusion / Mitsuba | multiple, octaves / Mitsuba | "
          "multiple, floor |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in reports:
        s, t = r["single_scattering"], r["transmittance"]
        ms = r.get("multiple_scattering")
        ms_cell = (f"{ms['diffusion']['ratio']:.3f} | {ms['octaves']['ratio']:.3f} | ±{100 * ms['noise_floor']:.1f} %"
                   if ms else "— | — | —")
        print(f"| {os.path.basename(r['scene'])} | {r['cloudy_pixels']} | "
              f"{pct(s['nimbus_vs_mitsuba']['mean_signed'])} | ±{100 * s['mean_noise']:.2f} % | "
              f"{s['nimbus_vs_mitsuba']['mean_abs'] / max(s['noise_floor']['mean_abs'], 1e-12):.2f} | "
              f"{t['nimbus_vs_mitsuba']['mean_abs']:.4f} / {t['noise_floor']['mean_abs']:.4f} | "
              f"{edge_cell(r['thin_edges'])} | {ms_cell} |")


def agree(a, mi, scene_path, reach, work, voxel):
    """Nimbus against Mitsuba on one view, on a grid of `voxel` metres; the report as
    agreement.json holds it."""
    width, height = (int(v) for v in a.resolution.lower().split("x"))
    vol, xml, exr = (os.path.join(work, n) for n in ("density.vol", "scene.xml", "nimbus.exr"))
    t0 = time.time()
    export_args = [a.nimbus, "export-density", scene_path, "-o", vol, "--mitsuba", xml, "--force",
                   "--voxel", str(voxel), "--filter", str(a.filter)]
    if reach is not None:
        export_args += ["--reach", str(reach)]
    if a.multiple_scattering:
        export_args += ["--margin", str(a.margin)]
    export = run(export_args)
    t_export = time.time() - t0
    cloudy_voxels = next((l for l in export.splitlines() if "voxels cloudy" in l), "")
    if " 0 of " in cloudy_voxels:
        refuse(f"{os.path.relpath(scene_path, ROOT)}: the exported region holds no cloud "
               f"({cloudy_voxels.strip()}): choose a view that sees clouds")
    t0 = time.time()
    render = run([a.nimbus, "render", scene_path, "--verification", "--format", "exr", "-r", a.resolution,
                  "-f", str(a.frames), "-o", exr, "--force"])
    t_nimbus = time.time() - t0
    adapter = next((l[len("adapter: "):] for l in render.splitlines() if l.startswith("adapter: ")), "?")
    n = read_exr(exr)
    nimbus_l = n["clouds.R"]
    nimbus_t = n["clouds.transmittance"]
    if not (nimbus_t < 0.999).any():
        refuse(f"{os.path.relpath(scene_path, ROOT)}: the view sees no cloud (Nimbus's "
               f"transmittance is 1 at every pixel), so there is nothing to compare: choose a "
               f"view that sees clouds")

    t0 = time.time()
    ss = [mitsuba_render(mi, xml, width, height, a.spp, seed, sun=a.sun_scale) for seed in (1, 2)]
    tr = [mitsuba_render(mi, xml, width, height, a.spp, seed, sun=0, sky=1, albedo=0) for seed in (3, 4)]
    t_mitsuba = time.time() - t0
    mit_l = [img[..., 0] for img in ss]
    mit_t = [img[..., 0] for img in tr]

    mask = (nimbus_t < 0.999) | (mit_t[0] < 0.999)
    cloudy = int(mask.sum())
    # Thin edges: the cloudy pixels whose transmittance (Mitsuba's, the mean of its two renders,
    # so the mask does not favour either model) is at least 0.9. They hold little of the image's
    # light, so the image mean cannot show a bias there; their own mean and floor can.
    edge = mask & (0.5 * (mit_t[0] + mit_t[1]) >= THIN_EDGE)
    report = {
        "scene": os.path.relpath(scene_path, ROOT),
        "resolution": [width, height],
        "voxel_m": voxel,
        "filter": a.filter,
        "mitsuba": {"version": mi.__version__, "variant": a.variant, "spp": a.spp, "sun_scale": a.sun_scale},
        "nimbus": {"adapter": adapter, "frames": a.frames},
        "cloudy_pixels": cloudy,
        "seconds": {"export": t_export, "nimbus": t_nimbus, "mitsuba": t_mitsuba},
        "single_scattering": {
            # Both against Mitsuba's first render, so both carry its noise once.
            "nimbus_vs_mitsuba": compare(nimbus_l, mit_l[0], mask),
            "mitsuba_vs_mitsuba": compare(mit_l[1], mit_l[0], mask),
            "noise_floor": one_render(compare(mit_l[1], mit_l[0], mask)),
            # The noise of one render's image mean (the bar the image mean is held to).
            "mean_noise": mean_noise(mit_l[0], mit_l[1], mask),
            "mean_ratio": float(nimbus_l[mask].mean() / (0.5 * (mit_l[0] + mit_l[1]))[mask].mean()),
        },
        "thin_edges": thin_edges(nimbus_l, mit_l, edge),
        # Transmittance differences as absolute values (it is already a fraction).
        "transmittance": {
            "nimbus_vs_mitsuba": absolute(nimbus_t, mit_t[0], mask),
            "mitsuba_vs_mitsuba": absolute(mit_t[1], mit_t[0], mask),
            "noise_floor": one_render(absolute(mit_t[1], mit_t[0], mask)),
            "mean_nimbus": float(nimbus_t[mask].mean()),
            "mean_mitsuba": float(0.5 * (mit_t[0] + mit_t[1])[mask].mean()),
        },
    }

    if a.multiple_scattering:
        models = {}
        for model, flags in (("diffusion", ["--enable", "diffusion"]), ("octaves", ["--octaves", "8"])):
            ms_exr = os.path.join(work, f"nimbus-{model}.exr")
            run([a.nimbus, "render", scene_path, "--verification", *flags, "--format", "exr",
                 "-r", a.resolution, "-f", str(a.frames), "-o", ms_exr, "--force"])
            models[model] = read_exr(ms_exr)["clouds.R"]
        spp = a.ms_spp or a.spp
        full = [mitsuba_render(mi, xml, width, height, spp, seed, max_depth=-1)[..., 0] for seed in (5, 6)]
        reference = 0.5 * (full[0] + full[1])
        mean = reference[mask].mean()
        report["multiple_scattering"] = {
            "mitsuba_mean": float(mean),
            "mitsuba_spp": spp,
            # The noise of one render's image mean (its standard error over the pixels); the
            # ratios below are against the mean of the two, whose noise is 1/sqrt(2) of it.
            "noise_floor": mean_noise(full[0], full[1], mask),
            "single_over_full_mitsuba": float(0.5 * (mit_l[0] + mit_l[1])[mask].mean() / mean),
        }
        for model, image in models.items():
            report["multiple_scattering"][model] = {
                "nimbus_mean": float(image[mask].mean()),
                "ratio": float(image[mask].mean() / mean),
            }
        np.save(os.path.join(work, "mitsuba_full.npy"), reference)

    report["work"] = work
    with open(os.path.join(work, "agreement.json"), "w") as f:
        json.dump(report, f, indent=2)
    np.save(os.path.join(work, "mitsuba_single.npy"), 0.5 * (mit_l[0] + mit_l[1]))
    np.save(os.path.join(work, "mitsuba_renders.npy"), np.stack(mit_l + mit_t))
    # Side by side: Nimbus, Mitsuba, and their difference ×4 (red: Nimbus brighter, blue:
    # darker), scaled so the brightest cloud pixel is white.
    scale = 1.0 / max(np.percentile(mit_l[0][mask], 99.5), 1e-12)
    grey = lambda img: np.repeat((img * scale)[..., None], 3, axis=2)
    diff = 4.0 * (nimbus_l - mit_l[0]) * scale
    signed = np.stack([np.clip(diff, 0, None), np.zeros_like(diff), np.clip(-diff, 0, None)], axis=2)
    gap = np.ones((height, 2, 3))
    strip = np.concatenate([grey(nimbus_l), gap, grey(mit_l[0]), gap, signed], axis=1)
    mi.util.write_bitmap(os.path.join(work, "comparison.png"), np.clip(strip, 0, 1).astype(np.float32))

    return report


def print_report(report, work):
    width, height = report["resolution"]
    cloudy = report["cloudy_pixels"]
    a_voxel, a_filter = report["voxel_m"], report["filter"]
    adapter, frames = report["nimbus"]["adapter"], report["nimbus"]["frames"]
    m = report["mitsuba"]
    t_export, t_nimbus, t_mitsuba = (report["seconds"][k] for k in ("export", "nimbus", "mitsuba"))
    s, t = report["single_scattering"], report["transmittance"]
    print()
    print(f"scene {report['scene']}, {width}x{height}, {cloudy} cloudy pixels; grid voxels {a_voxel} m "
          f"averaged over {a_filter}^3 samples; Nimbus {frames} frames on {adapter}; "
          f"Mitsuba {m['version']} {m['variant']}, {m['spp']} spp x 2 seeds")
    print()
    print("| | image mean | per pixel, mean | per pixel, p95 |")
    print("|---|---|---|---|")
    for label, key, fmt in (("single scattering, Nimbus vs Mitsuba", "nimbus_vs_mitsuba", pct),
                            ("single scattering, one Mitsuba render's noise (floor)", "noise_floor", pct)):
        r = s[key]
        print(f"| {label} | {fmt(r['mean_signed'])} | {fmt(r['mean_abs'])} | {fmt(r['p95_abs'])} |")
    for label, key in (("transmittance, Nimbus vs Mitsuba", "nimbus_vs_mitsuba"),
                       ("transmittance, one Mitsuba render's noise (floor)", "noise_floor")):
        r = t[key]
        print(f"| {label} (absolute) | {r['mean_signed']:+.4f} | {r['mean_abs']:.4f} | {r['p95_abs']:.4f} |")
    print(f"\nimage mean, single scattering: {pct(report['single_scattering']['nimbus_vs_mitsuba']['mean_signed'])} "
          f"± {100 * report['single_scattering']['mean_noise']:.2f} % (one render's standard error)")
    print(f"thin edges (transmittance >= {THIN_EDGE}), single scattering: {edge_cell(report['thin_edges'])}")
    if "multiple_scattering" in report:
        m = report["multiple_scattering"]
        print(f"\nmultiple scattering against Mitsuba's full path tracer ({m['mitsuba_spp']} spp x 2, "
              f"noise ±{100 * m['noise_floor']:.2f} %): Nimbus's diffusion {m['diffusion']['ratio']:.3f}, "
              f"its octaves {m['octaves']['ratio']:.3f} (single / full in Mitsuba: "
              f"{m['single_over_full_mitsuba']:.3f})")
    print(f"\ntimes: export {t_export:.1f} s, Nimbus {t_nimbus:.1f} s, Mitsuba {t_mitsuba:.1f} s; "
          f"files in {work}")


if __name__ == "__main__":
    sys.exit(main())
