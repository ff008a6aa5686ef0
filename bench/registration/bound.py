#!/usr/bin/python3
"""How well could any method register each sim-pairs pair? An information bound.

For the overlapping source points of each pair (placed by the truth), the
point-to-plane Fisher information with each point's range noise
(k rho^2 along its ray, projected on the surface normal), inverted, gives
the covariance of the best unbiased estimate of the six-degree-of-freedom
motion; its displacement at the source's scanner, times sqrt(2) because the
target is as noisy as the source, is printed as a share of the distance
between the scanners, next to the 1 % success line of compare.py.

Optimistic by construction: the normals are fitted to the moved source
points on 0.5 m cells (at heavy noise they come out smoother than the
ground), and a real method must also estimate the target's surface. A
method far above the bound is short of what the data hold; one near it
can only gain from more data.

  build/bin/ambler-cli sim-pairs --out /tmp/pairs    # evaluation pairs (--tuning for the others)
  /usr/bin/python3 bench/registration/bound.py /tmp/pairs/pairs.json

Needs Debian's python3-numpy.
"""
import argparse
import json

import numpy as np


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


def normals(points, cell=0.5, least=6):
    """Upward plane normal of each point's xy cell (NaN where too few points)."""
    keys = cell_keys(points[:, :2], cell)
    order = np.argsort(keys, kind="stable")
    out = np.full(points.shape, np.nan)
    for group in np.split(order, np.flatnonzero(np.diff(keys[order])) + 1):
        if len(group) < least:
            continue
        centred = points[group] - points[group].mean(0)
        n = np.linalg.eigh(centred.T @ centred)[1][:, 0]
        out[group] = n if n[2] > 0 else -n
    return out


def bound(pair):
    frame = pair["world"]
    source, source_viewpoint = read_pcd(frame["source"])
    target, _ = read_pcd(frame["target"])
    truth = np.array(frame["truth"])
    placed = source @ truth[:3, :3].T + truth[:3, 3]
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
    return len(placed), error


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pairs", help="pairs.json written by ambler-cli sim-pairs")
    args = ap.parse_args()
    rows = []
    for pair in json.load(open(args.pairs))["pairs"]:
        if pair["foreign"]:
            continue
        points, error = bound(pair)
        share = 100 * error / pair["distance_m"]
        rows.append(share)
        print(f"{pair['name']} {pair['family']:9s} k={pair['noise_k']:<8g} "
              f"{pair['distance_m']:.2f} m apart, {points:6d} points in the overlap: "
              f"bound {1000 * error:5.1f} mm, {share:.3f} % of the distance")
    print(f"bound over {len(rows)} pairs: median {np.median(rows):.3f} %, max {max(rows):.3f} %")


if __name__ == "__main__":
    main()
