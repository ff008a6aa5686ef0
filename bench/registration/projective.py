#!/usr/bin/python3
"""A range-image residual for registration, tried on sim-pairs pairs (a prototype).

The target's cloud is put back into its scanner's image: about its
viewpoint, in the levelled frame that sim-pairs writes, a point's column
angle is asin(x / rho) and its row angle atan2(z, y) (the scanner's tilt is
a turn about x, which leaves both regular); the angular steps are the
commonest gaps between neighbouring distinct angles. Each raw source point,
placed by the motion, is compared with the target's range interpolated
bilinearly at its direction, along the target's ray: residual rho - R, whose
variance is the four pixels' range noise (k rho^2, sim-pairs' k) through the
interpolation weights, the source point's own k rho^2 and 2 mm. Huber at 2
sigma; Levenberg-Marquardt on the six degrees of freedom (numerical
Jacobians), each step lowering the cost, in which a point off the target's
image counts as one at 3 sigma.

The target's noise enters pixel by pixel, independent from one quad to the
next, instead of through planes fitted to blocks of points. Started from the
truth, the fit shows whether a minimum lies there within compare.py's
bounds; started from `register`'s answer (or the guess), whether a local fit
reaches it; each line also gives the cost where the fit ended and at the
truth, which tells whether the truth is the cost's lowest point.

  build/bin/ambler-cli sim-pairs --tuning --count 48 --foreign 0 --noise 0.0005 0.001 --out /tmp/pairs48
  /usr/bin/python3 bench/registration/projective.py /tmp/pairs48/pairs.json --start truth
  /usr/bin/python3 bench/registration/projective.py /tmp/pairs48/pairs.json --start register

Needs Debian's python3-numpy; --start register runs build/bin/ambler-cli.
docs/mapping.md (Registration against Open3D) has the figures.
"""
import argparse
import json
import math
import os
import subprocess

import numpy as np

from bound import read_pcd

HERE = os.path.dirname(os.path.abspath(__file__))
CLI = os.path.join(HERE, "..", "..", "build", "bin", "ambler-cli")
POINT_FLOOR_M = 0.002
HUBER_SIGMAS = 2.0
MAX_RESIDUAL_M = 0.5


def read_levelled(path):
    """Points of a levelled sim-pairs cloud (its VIEWPOINT at the origin)."""
    points, viewpoint = read_pcd(path)
    if viewpoint.any():
        raise SystemExit(f"{path}: expected the levelled cloud (VIEWPOINT at the origin)")
    return points


def ray_angles(points):
    """Range, column angle and row angle of points about the origin."""
    rho = np.linalg.norm(points, axis=1)
    column = np.arcsin(np.clip(points[:, 0] / rho, -1, 1))
    row = np.arctan2(points[:, 2], points[:, 1])
    return rho, column, row


def grid_of(angles):
    """First angle, step and each angle's index on a regular grid: the step first
    the commonest gap between neighbouring distinct angles, then fitted to all."""
    distinct = np.unique(np.round(angles, 7))
    gaps = np.diff(distinct)
    step = np.median(gaps[gaps > 1e-6])
    index = np.rint((angles - angles.min()) / step).astype(int)
    slope, first = np.polyfit(index, angles, 1)
    return first, slope, np.rint((angles - first) / slope).astype(int)


class RangeImage:
    """The target's ranges on its scanner's angular grid, NaN without a return."""

    def __init__(self, points):
        rho, column, row = ray_angles(points)
        self.col0, self.col_step, c = grid_of(column)
        self.row0, self.row_step, r = grid_of(row)
        off_grid = max(np.abs((column - self.col0) / self.col_step - c).max(),
                       np.abs((row - self.row0) / self.row_step - r).max())
        if off_grid > 0.01:
            raise SystemExit(f"the target's points lie {off_grid:.3f} steps off any grid")
        self.range = np.full((r.max() + 1, c.max() + 1), np.nan)
        self.range[r, c] = rho

    def interpolate(self, column, row):
        """Bilinear range at fractional directions, and the sum of squared weights."""
        # A direction that is not finite falls off the image, as -1.
        cf = np.nan_to_num((column - self.col0) / self.col_step, nan=-1.0)
        rf = np.nan_to_num((row - self.row0) / self.row_step, nan=-1.0)
        rows, cols = self.range.shape
        c0 = np.floor(cf).astype(int)
        r0 = np.floor(rf).astype(int)
        inside = (c0 >= 0) & (c0 < cols - 1) & (r0 >= 0) & (r0 < rows - 1)
        c0, r0 = np.clip(c0, 0, cols - 2), np.clip(r0, 0, rows - 2)
        fc, fr = cf - c0, rf - r0
        a = self.range
        value = ((1 - fr) * ((1 - fc) * a[r0, c0] + fc * a[r0, c0 + 1]) +
                 fr * ((1 - fc) * a[r0 + 1, c0] + fc * a[r0 + 1, c0 + 1]))
        weights2 = ((1 - fr) * (1 - fc))**2 + ((1 - fr) * fc)**2 + (fr * (1 - fc))**2 + (fr * fc)**2
        value[~inside] = np.nan
        return value, weights2


def motion(x):
    """4 x 4 transform of a shift x[:3] and a rotation vector x[3:]."""
    angle = np.linalg.norm(x[3:])
    skew = np.array([[0, -x[5], x[4]], [x[5], 0, -x[3]], [-x[4], x[3], 0]])
    if angle < 1e-12:
        rotation = np.eye(3) + skew
    else:
        k = skew / angle
        rotation = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = rotation, x[:3]
    return t


PROPAGATE_SOURCE_NOISE = False


def range_residual(placed, image):
    rho, column, row = ray_angles(placed)
    target_rho, weights2 = image.interpolate(column, row)
    return rho - target_rho, target_rho, weights2


def residuals(transform, source, source_rho, image, k):
    placed = source @ transform[:3, :3].T + transform[:3, 3]
    e, target_rho, weights2 = range_residual(placed, image)
    gain = 1.0
    if PROPAGATE_SOURCE_NOISE:
        # How much the residual moves when the source point moves along its
        # own ray, where its noise lies (1 cm, a first-order propagation).
        along = (source / source_rho[:, None]) @ transform[:3, :3].T
        gain = (range_residual(placed + 0.01 * along, image)[0] - e) / 0.01
    variance = ((k * target_rho**2)**2 * weights2 + (k * source_rho**2 * gain)**2 +
                POINT_FLOOR_M**2)
    # A point whose step along its ray leaves the image is left out with it.
    return np.where(np.isfinite(variance), e, np.nan), variance


def inside(e):
    """Residuals on the target's image and within MAX_RESIDUAL_M."""
    return np.isfinite(e) & (np.abs(e) < MAX_RESIDUAL_M)


def cost(e, variance):
    """Huber cost of residuals; a point off the target's image (or farther off
    than MAX_RESIDUAL_M) counts as one at 3 sigma, so that a motion cannot
    lower the cost by losing overlap."""
    used = inside(e)
    z = np.abs(e[used]) / np.sqrt(variance[used])
    h = HUBER_SIGMAS
    return (np.where(z < h, 0.5 * z * z, h * z - 0.5 * h * h).sum() +
            (~used).sum() * (3 * h - 0.5 * h * h))


def fit(start, source, image, k, iterations):
    """Levenberg-Marquardt: a step is taken only where it lowers the cost."""
    transform = start.copy()
    source_rho = np.linalg.norm(source, axis=1)
    e, variance = residuals(transform, source, source_rho, image, k)
    damping, current = 1e-3, cost(e, variance)
    for _ in range(iterations):
        used = inside(e)
        jacobian = np.zeros((used.sum(), 6))
        for j in range(6):  # central differences: 0.1 mm, 0.01 mrad
            dx = np.zeros(6)
            dx[j] = 1e-4 if j < 3 else 1e-5
            ahead, _ = residuals(motion(dx) @ transform, source[used], source_rho[used], image, k)
            behind, _ = residuals(motion(-dx) @ transform, source[used], source_rho[used], image, k)
            jacobian[:, j] = (ahead - behind) / (2 * dx[j])
        good = np.isfinite(jacobian).all(1)
        jac, err, sigma = jacobian[good], e[used][good], np.sqrt(variance[used][good])
        z = np.abs(err) / sigma
        weight = np.where(z < HUBER_SIGMAS, 1.0, HUBER_SIGMAS / z) / sigma**2
        normal, gradient = jac.T @ (jac * weight[:, None]), jac.T @ (weight * err)
        for _ in range(10):
            step = -np.linalg.solve(normal + damping * np.diag(np.diag(normal)), gradient)
            moved = motion(step) @ transform
            moved_e, moved_variance = residuals(moved, source, source_rho, image, k)
            moved_cost = cost(moved_e, moved_variance)
            if moved_cost < current:
                transform, current, damping = moved, moved_cost, max(damping / 3, 1e-6)
                e, variance = moved_e, moved_variance
                break
            damping *= 4
        else:
            break
        if np.linalg.norm(step[:3]) < 1e-5 and np.linalg.norm(step[3:]) < 1e-6:
            break
    return transform, current


def error(found, truth, distance):
    """Error % of the distance at the source's scanner, and angle [deg] (compare.py's rule)."""
    d = np.linalg.inv(truth) @ found
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(d[:3, :3]) - 1) / 2))))
    shift = np.linalg.norm(found[:3, 3] - truth[:3, 3])
    return 100 * shift / distance, angle


def start_of(pair, frame, how):
    if how == "truth":
        return np.array(frame["truth"])
    if how == "guess":
        return np.array(frame["guess"])
    out = subprocess.run([CLI, "register", frame["source"], frame["target"], "--initial",
                          frame["initial"], "--about", frame["about"], "--json"],
                         capture_output=True, text=True)
    if not out.stdout.strip():
        raise SystemExit(f"pair {pair['name']}: register printed nothing: {out.stderr.strip()}")
    return np.array(json.loads(out.stdout)["transform"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pairs", help="pairs.json of sim-pairs (levelled clouds are used)")
    parser.add_argument("--start", choices=["truth", "guess", "register"], default="truth")
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--propagate-source-noise", action="store_true",
                        help="the source point's noise through the residual's change along its "
                             "ray, instead of as it is")
    a = parser.parse_args()
    global PROPAGATE_SOURCE_NOISE
    PROPAGATE_SOURCE_NOISE = a.propagate_source_noise
    pairs = [p for p in json.load(open(a.pairs))["pairs"] if not p["foreign"]]
    landed = started = 0
    for pair in pairs:
        frame = pair["levelled"]
        truth = np.array(frame["truth"])
        start = start_of(pair, frame, a.start)
        image = RangeImage(read_levelled(frame["target"]))
        source = read_levelled(frame["source"])
        found, found_cost = fit(start, source, image, pair["noise_k"], a.iterations)
        truth_cost = cost(*residuals(truth, source, np.linalg.norm(source, axis=1), image,
                                     pair["noise_k"]))
        before, after = error(start, truth, pair["distance_m"]), error(found, truth, pair["distance_m"])
        within = [e <= 1.0 and angle <= 0.5 for e, angle in (before, after)]
        started += within[0]
        landed += within[1]
        print(f"{pair['name']} {pair['family']:<9} k={pair['noise_k']:g} d={pair['distance_m']:.2f} m: "
              f"start {before[0]:.3f} % {before[1]:.3f} deg -> {after[0]:.3f} % {after[1]:.3f} deg,"
              f" cost {found_cost:.0f} (truth {truth_cost:.0f}){'' if within[1] else '  miss'}",
              flush=True)
    print(f"within 1 % and 0.5 deg: {started} of {len(pairs)} at the start ({a.start}), "
          f"{landed} after the fit")


if __name__ == "__main__":
    main()
