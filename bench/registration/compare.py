#!/usr/bin/python3
"""Registration side by side: `ambler-cli register` and Open3D on the same pairs.

Generates the pairs with `ambler-cli sim-pairs` (evaluation pairs unless
--tuning), registers each pair in both input frames (levelled about the
sensor, and the world frame) with every method from the same initial guess,
and prints one table (and --json, the figures). Success: within 1 % of the
distance between the two scanners and 0.5 deg. Pairs of two different
terrains ("foreign") must be refused: `register` exits non-zero, a peer has
no refusal and counts as accepting.

Open3D is Debian's python3-open3d (a benchmark-only dependency); run with
Debian's /usr/bin/python3.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CLI = os.path.join(HERE, "..", "..", "build", "bin", "ambler-cli")


def error(found, truth, distance, scanner):
    """Error % of the distance at the source's scanner, and angle [deg]."""
    d = np.linalg.inv(truth) @ found
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(d[:3, :3]) - 1) / 2))))
    at = np.append(scanner, 1.0)
    shift = np.linalg.norm((found @ at)[:3] - (truth @ at)[:3])
    return 100 * shift / distance, angle


def run_ambler(frame):
    start = time.perf_counter()
    proc = subprocess.run(
        [CLI, "register", frame["source"], frame["target"], "--initial", frame["initial"],
         "--about", frame["about"], "--json"], capture_output=True, text=True)
    wall = time.perf_counter() - start
    out = json.loads(proc.stdout) if proc.stdout.strip() else None
    return {
        "transform": np.array(out["transform"]) if out else None,
        "refused": proc.returncode != 0,
        "verdict": out["quality"]["verdict"] if out else "error",
        "s": out["ms"] / 1000 if out else wall,  # reading the clouds included
        "process_s": wall,
    }


def open3d_methods(o3d, voxel, distance):
    reg = o3d.pipelines.registration
    criteria = reg.ICPConvergenceCriteria(max_iteration=60)

    def prepared(path):
        cloud = o3d.io.read_point_cloud(path).voxel_down_sample(voxel)
        return cloud

    def gicp(source, target, guess):
        return reg.registration_generalized_icp(
            source, target, distance, guess,
            reg.TransformationEstimationForGeneralizedICP(), criteria)

    def plane(source, target, guess):
        for c in (source, target):
            c.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=3 * voxel, max_nn=30))
        loss = reg.TukeyLoss(k=0.1)
        return reg.registration_icp(source, target, distance, guess,
                                    reg.TransformationEstimationPointToPlane(loss), criteria)

    def run(method):
        def go(frame):
            start = time.perf_counter()
            source, target = prepared(frame["source"]), prepared(frame["target"])
            r = method(source, target, np.array(frame["guess"]))
            return {"transform": np.asarray(r.transformation), "refused": False,
                    "verdict": "-", "s": time.perf_counter() - start}
        return go

    return {"Open3D generalized ICP": run(gicp), "Open3D point-to-plane + Tukey": run(plane)}


def summary(rows, name):
    out = {"method": name,
           "has_verdict": any(r["verdict"] != "-" for r in rows if r["method"] == name)}
    for frame in ("levelled", "world"):
        mine = [r for r in rows if r["method"] == name and r["frame"] == frame]
        good = [r for r in mine if not r["foreign"]]
        bad = [r for r in mine if r["foreign"]]
        errors = [r["err_pct"] for r in good if r["err_pct"] is not None]
        out[frame] = {
            "pairs": len(good),
            "successes": sum(r["success"] for r in good),
            "err_pct_median": statistics.median(errors) if errors else None,
            "err_pct_max": max(errors) if errors else None,
            "err_deg_max": max(r["err_deg"] for r in good) if good else None,
            "trusted_but_out_of_bounds": sum(r["verdict"] == "trusted" and not r["success"]
                                             for r in good),
            "trusted_within_bounds": sum(r["verdict"] == "trusted" and r["success"]
                                         for r in good),
            "foreign_refused": sum(r["refused"] for r in bad),
            "foreign": len(bad),
            "s_median": statistics.median(r["s"] for r in mine) if mine else None,
        }
    return out


def information_bound(pairs):
    """bound.py's figures for each overlapping pair, and the successes to expect at it."""
    import bound
    out = {r["pair"]["name"]: {"bound_pct": r["bound_pct"], "chance": r["chance"]}
           for r in bound.pair_bounds(pairs)}
    return {"pairs": out, "expected_successes": sum(v["chance"] for v in out.values())}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tuning", action="store_true", help="the tuning pairs (seeds from 1)")
    ap.add_argument("--count", type=int, default=24, help="overlapping pairs")
    ap.add_argument("--foreign", type=int, default=6, help="pairs of two different terrains")
    ap.add_argument("--pairs", help="an existing sim-pairs folder instead of generating one")
    ap.add_argument("--no-open3d", action="store_true", help="only ambler-cli")
    ap.add_argument("--no-bound", action="store_true",
                    help="without the information bound's line (bound.py; makes the pairs' "
                         "noise-free twin)")
    # Open3D's settings: the best of voxel 0.1/0.2 m x distance 0.3/0.5/1 m on
    # the tuning pairs (10 of 24 levelled pairs within bounds at 0.1/0.3).
    ap.add_argument("--o3d-voxel", type=float, default=0.1, help="Open3D's thinning [m]")
    ap.add_argument("--o3d-distance", type=float, default=0.3,
                    help="Open3D's largest pairing distance [m]")
    ap.add_argument("--json", metavar="FILE", help="also write every figure and row there")
    args = ap.parse_args()

    folder = args.pairs
    if folder is None:
        folder = tempfile.mkdtemp(prefix="ambler-pairs-")
        cmd = [CLI, "sim-pairs", "--out", folder, "--count", str(args.count),
               "--foreign", str(args.foreign)] + (["--tuning"] if args.tuning else [])
        subprocess.run(cmd, check=True, capture_output=True)
    pairs = json.load(open(os.path.join(folder, "pairs.json")))
    print(f"pairs in {folder}", file=sys.stderr)

    methods = {"ambler-cli register": run_ambler}
    if not args.no_open3d:
        import open3d as o3d
        o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
        methods.update(open3d_methods(o3d, args.o3d_voxel, args.o3d_distance))

    rows = []
    for p in pairs["pairs"]:
        for frame in ("levelled", "world"):
            f = p[frame]
            truth = np.array(f["truth"])
            for name, method in methods.items():
                r = method(f)
                row = {"pair": p["name"], "family": p["family"], "foreign": p["foreign"],
                       "frame": frame, "method": name, "refused": r["refused"],
                       "verdict": r["verdict"], "s": r["s"], "err_pct": None,
                       "err_deg": None, "success": False}
                if not p["foreign"] and r["transform"] is not None:
                    scanner = np.array([float(v) for v in f["about"].split(",")])
                    pct, deg = error(r["transform"], truth, p["distance_m"], scanner)
                    row.update(err_pct=float(pct), err_deg=float(deg),
                               success=bool(pct <= 1.0 and deg <= 0.5))
                rows.append(row)
                print(f"{p['name']} {p['family']:8s} {frame:8s} {name:30s} "
                      f"{row['err_pct'] if row['err_pct'] is not None else float('nan'):8.3f} % "
                      f"{row['err_deg'] if row['err_deg'] is not None else float('nan'):6.3f} deg "
                      f"{r['verdict']:10s} {r['s']:.3f} s", file=sys.stderr)

    table = [summary(rows, name) for name in methods]
    limit = None if args.no_bound else information_bound(pairs)
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"set": pairs["set"], "pairs": folder, "summary": table, "rows": rows,
                       "bound": limit}, out, indent=1, default=lambda v: v.item())
    print(f"{pairs['set']} pairs: {len([p for p in pairs['pairs'] if not p['foreign']])} "
          f"overlapping + {len([p for p in pairs['pairs'] if p['foreign']])} of two terrains")
    print("| method | error % of distance, median / max (levelled; world) | successes, "
          "levelled + world | trusted: within / out of bounds | foreign refused | wall time per "
          "pair, median |")
    print("|---|---|---|---|---|---|")
    for t in table:
        lv, wd = t["levelled"], t["world"]
        fmt = lambda v: "-" if v is None else f"{v:.2f}"
        trusted = (f"{lv['trusted_within_bounds'] + wd['trusted_within_bounds']} / "
                   f"{lv['trusted_but_out_of_bounds'] + wd['trusted_but_out_of_bounds']}"
                   if t["has_verdict"] else "-")
        print(f"| {t['method']} | {fmt(lv['err_pct_median'])} / {fmt(lv['err_pct_max'])}; "
              f"{fmt(wd['err_pct_median'])} / {fmt(wd['err_pct_max'])} | "
              f"{lv['successes']}/{lv['pairs']} + {wd['successes']}/{wd['pairs']} | "
              f"{trusted} | "
              f"{lv['foreign_refused'] + wd['foreign_refused']}/{lv['foreign'] + wd['foreign']} | "
              f"{lv['s_median']:.3f} s |")
    if limit:
        print(f"An estimator at the information bound (bound.py: both surfaces known) would "
              f"land on {limit['expected_successes']:.1f} of {len(limit['pairs'])} pairs "
              f"({100 * limit['expected_successes'] / len(limit['pairs']):.0f} %).")


if __name__ == "__main__":
    main()
