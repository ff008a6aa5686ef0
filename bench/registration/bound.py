#!/usr/bin/python3
"""How well could any method register each sim-pairs pair? An information bound.

Each pair is scanned a second time without range noise (`sim-pairs --noise 0`
with the same seeds: the same rays, the same order), so every noisy point
has its true place and the true surface's normal there. For the source's
true points over ground the target saw (placed by the truth), the
point-to-plane Fisher information with each point's range noise
(k rho^2 along its ray, projected on the surface normal), inverted, gives
the covariance of the best unbiased estimate of the six-degree-of-freedom
motion when the surface is known; its displacement at the source's
scanner, times sqrt(2) because the target is as noisy as the source, is
printed as a share of the distance between the scanners, next to the 1 %
success line of compare.py.

Also printed: the chance that an estimate at the bound (Gaussian, that
covariance) meets compare.py's rule. Optimistic still: a real method must
estimate both surfaces from the noisy points. A method far above the bound
is short of what the data hold.

  build/bin/ambler-cli sim-pairs --out /tmp/pairs    # evaluation pairs (--tuning for the others)
  /usr/bin/python3 bench/registration/bound.py /tmp/pairs/pairs.json

Needs Debian's python3-numpy. The noise-free twin is made with
build/bin/ambler-cli unless --clean names one made before.
"""
import argparse
import json
import os
import subprocess
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CLI = os.path.join(HERE, "..", "..", "build", "bin", "ambler-cli")


def read_pcd(path):
    """Points (finite ones) and the VIEWPOINT of a binary x y z float PCD."""
    header = {}
    with open(path, "rb") as f:
        while True:
            key, *values = f.readline().decode().split()
            header[key] = values
            if key == "DATA":
                break
        if header["DATA"] != ["binary"] or header["FIELDS"] != ["x", "y", "z"]:
            raise SystemExit(f"{path}: expected a binary x y z PCD")
        n = int(header["POINTS"][0])
        points = np.frombuffer(f.read(12 * n), dtype="<f4").reshape(n, 3).astype(float)
    return points[np.isfinite(points).all(1)], np.array([float(v) for v in header["VIEWPOINT"][:3]])


def cell_keys(xy, cell):
    k = np.floor(xy / cell).astype(np.int64)
    return k[:, 0] * 1_000_003 + k[:, 1]


def normals(points, cells=(0.2, 0.4, 0.8, 1.6), least=6):
    """Upward plane normal at each point: of its smallest xy cell holding `least` points."""
    out = np.full(points.shape, np.nan)
    for cell in cells:
        _, group, count = np.unique(cell_keys(points[:, :2], cell), return_inverse=True,
                                    return_counts=True)
        sums = np.stack([np.bincount(group, points[:, a]) for a in range(3)], 1)
        outer = np.stack([np.stack([np.bincount(group, points[:, a] * points[:, b])
                                    for b in range(3)], 1) for a in range(3)], 1)
        mean = sums / count[:, None]
        cov = outer / count[:, None, None] - mean[:, :, None] * mean[:, None, :]
        n = np.linalg.eigh(cov)[1][:, :, 0]
        n[n[:, 2] < 0] *= -1
        fill = np.isnan(out[:, 0]) & (count[group] >= least)
        out[fill] = n[group[fill]]
    return out


def noise_free_twin(pairs, folder):
    """The pairs made again in `folder` without range noise (same seeds, rays and order)."""
    foreign = sum(p["foreign"] for p in pairs["pairs"])
    cmd = [CLI, "sim-pairs", "--out", folder, "--noise", "0", "--count",
           str(len(pairs["pairs"]) - foreign), "--foreign", str(foreign)]
    subprocess.run(cmd + (["--tuning"] if pairs["set"] == "tuning" else []), check=True,
                   capture_output=True)


def pair_bounds(pairs, clean=None):
    """For each overlapping pair: the pair, points in the overlap, bound [m], bound as a
    share of the distance [%] and chance of landing; `clean` is the noise-free twin's
    folder, made (and removed) here when None."""
    with tempfile.TemporaryDirectory(prefix="ambler-pairs-clean-") as made:
        if clean is None:
            noise_free_twin(pairs, made)
            clean = made
        twins = {p["name"]: p for p in json.load(open(os.path.join(clean, "pairs.json")))["pairs"]}
        rows = []
        for pair in pairs["pairs"]:
            if not pair["foreign"]:
                points, error, chance = bound(pair, twins[pair["name"]])
                rows.append({"pair": pair, "points": points, "bound_m": error,
                             "bound_pct": 100 * error / pair["distance_m"], "chance": chance})
        return rows


def bound(pair, clean_pair):
    frame, clean_frame = pair["world"], clean_pair["world"]
    source, source_viewpoint = read_pcd(frame["source"])
    true_source, _ = read_pcd(clean_frame["source"])
    target, _ = read_pcd(frame["target"])
    if len(true_source) != len(source) or clean_pair["distance_m"] != pair["distance_m"]:
        raise SystemExit(f"pair {pair['name']}: the noise-free twin is not the same scan "
                         "(were the pairs made with non-default sim-pairs options?)")
    truth = np.array(frame["truth"])
    placed = true_source @ truth[:3, :3].T + truth[:3, 3]
    scanner = truth[:3, :3] @ source_viewpoint + truth[:3, 3]
    # Overlap: source points over a 20 cm cell the target covers.
    placed = placed[np.isin(cell_keys(placed[:, :2], 0.2), cell_keys(target[:, :2], 0.2))]
    n = normals(placed)
    keep = np.isfinite(n).all(1)
    placed, n = placed[keep], n[keep]
    rays = placed - scanner
    rho = np.linalg.norm(rays, axis=1)
    along_normal = np.abs((n * rays).sum(1)) / rho
    sigma = np.maximum(pair["noise_k"] * rho**2 * along_normal, 1e-4)  # 0.1 mm floor: k = 0
    jacobian = np.hstack([n, np.cross(placed, n)])
    information = (jacobian / sigma[:, None] ** 2).T @ jacobian
    covariance = np.linalg.inv(information)
    sx, sy, sz = scanner
    at_scanner = np.hstack([np.eye(3), -np.array([[0, -sz, sy], [sz, 0, -sx], [-sy, sx, 0]])])
    error = np.sqrt(2 * np.trace(at_scanner @ covariance @ at_scanner.T))
    return len(placed), error, landing(2 * covariance, at_scanner, pair["distance_m"])


def landing(covariance, at_scanner, distance, draws=20000):
    """The chance that an estimate with this covariance meets compare.py's rule
    (within 1 % of the distance at the source's scanner and 0.5 deg)."""
    rng = np.random.default_rng(1)
    scale = np.linalg.cholesky(covariance + 1e-18 * np.eye(6))
    motion = rng.standard_normal((draws, 6)) @ scale.T  # (translation, rotation vector)
    shift = np.linalg.norm(motion @ at_scanner.T, axis=1)
    turn = np.degrees(np.linalg.norm(motion[:, 3:], axis=1))
    return float(np.mean((shift <= 0.01 * distance) & (turn <= 0.5)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pairs", help="pairs.json written by ambler-cli sim-pairs")
    ap.add_argument("--clean", help="the same pairs made with --noise 0 (made here when absent)")
    args = ap.parse_args()
    pairs = json.load(open(args.pairs))
    rows = pair_bounds(pairs, args.clean)
    for row in rows:
        pair = row["pair"]
        print(f"{pair['name']} {pair['family']:9s} k={pair['noise_k']:<8g} "
              f"{pair['distance_m']:.2f} m apart, {row['points']:6d} points in the overlap: "
              f"bound {1000 * row['bound_m']:5.1f} mm, {row['bound_pct']:.3f} % of the distance, "
              f"lands with chance {row['chance']:.2f}")
    shares = np.array([r["bound_pct"] for r in rows])
    chances = np.array([r["chance"] for r in rows])
    print(f"bound over {len(rows)} pairs: median {np.median(shares):.3f} %, max "
          f"{shares.max():.3f} %; above 0.5 %: {np.count_nonzero(shares > 0.5)}, above 1 %: "
          f"{np.count_nonzero(shares > 1)}; an estimator at the bound lands on "
          f"{chances.sum():.1f} of {len(rows)} ({100 * chances.mean():.0f} %)")


if __name__ == "__main__":
    main()
