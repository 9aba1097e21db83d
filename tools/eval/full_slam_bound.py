#!/usr/bin/python3
"""What the sensors allow when the map is built from the same data: the whole run smoothed at once
(full SLAM), started from the ground truth, as a reference for a SLAM run's ATE.

  tools/eval/full_slam_bound.py DATASET RUN [--start truth|dr] [--iterations N] [--out FILE.tum]
                                [--wheel-heading] [--json]

DATASET is a simulated dataset folder (groundtruth.csv, encoders.csv, gyro.csv, features.csv,
sensors.yaml and sim_landmarks.csv, whose ids are the features' track ids); RUN holds
dead_reckoning.tum (cleanslam-replay --out), the reference. The unknowns are a planar pose and a
residual gyro bias at every frame with features, and every landmark's position. The factors are
the motion between frames (encoder distance and gyro turn integrated between them, with the noise
of sensors.yaml: distance_noise per encoder interval, noise_density and scale_error on the turn;
the gyro's mean rate while the wheels stand still measures the bias, which walks with bias_walk
and starts within bias_instability), every feature's pixels (pixel_noise, Huber weights beyond two
standard deviations) and the first frame's pose, held at the truth (so that errors are relative
to it, as cleanslam-eval --align none measures them). Levenberg-Marquardt solves it from the
ground truth (poses and landmarks), so the result is the most likely trajectory near the truth:
non-causal and knowing the basin, it is what an estimator that builds its own map could reach at
best, where known_map_bound.py gives the map for free. --start dr starts it from dead reckoning
instead (landmarks triangulated from their rays): how far a local solver gets without knowing the
basin. It shares no code with the estimator; it takes a pinhole camera (no distortion).
--wheel-heading adds the wheels' turn between frames, w = (d_right - d_left) / wheel_base, as a
second measurement of the heading change, theta = (1 + s) w - c d with the wheels' heading scale s
and drift per metre c as two more unknowns (priors 0.2 and 0.5 rad/m), its noise distance_noise
per wheel and encoder interval: the bound for an estimator that fuses the wheels' heading
(cleanslam's, odometry.wheel_yaw_*).

Prints the dead reckoner's ATE and the smoothed trajectory's, both relative to the first frame (as
cleanslam-eval --align none), at the frames with features, and two RMS position standard
deviations there, linearized at the solution under the calibration's noise model: given all the
data (smoothing) and given the data up to each frame (filtering: the older keyframes marginalized
in a forward sweep). Where the data leave the trajectory loose (a stretch whose landmarks are seen
in no other stretch, joined to the rest only across long gaps), a solver started from the truth
stays near it, so the ATE flatters and the standard deviations tell, to first order: no
estimator's expected error is below the smoothing one, and no causal estimator's (a filter's,
which outputs each pose from the data so far) below the filtering one. --out writes the poses
(TUM). Exit status 1 when a file is missing or malformed, 2 on bad arguments."""

import argparse
import json
import math
import os
import sys

import numpy as np

import known_map_bound as kmb
import sighting_bound
from cleanslam_eval import trajectory

HUBER = 2.0  # standard deviations
BEHIND_COST = 4.0 * HUBER * HUBER  # an observation predicted behind the camera
STILL_MIN_S = 0.5  # standing still this long measures the gyro bias
LANDMARK_PRIOR_M = 10.0  # keeps a landmark seen from one place solvable; negligible otherwise
WHEEL_SCALE_SD = 0.2  # --wheel-heading: priors of the wheels' heading scale and drift per metre
WHEEL_DRIFT_SD = 0.5
DR_DEPTH_M = 1.5  # --start dr: a landmark not triangulated starts this far along its first ray


def wrap(a):
    return (a + np.pi) % (2.0 * np.pi) - np.pi


class Odometry(kmb.Odometry):
    """known_map_bound's encoders and gyro, walked between any two times, and the wheels' turn and
    its variance per encoder interval."""

    def __init__(self, dataset, sen):
        super().__init__(dataset, sen)
        base = sen.wheel_base if sen.wheel_base > 0.0 else 1.0
        self.wheel_turn = (self.right - self.left) / base
        self.wheel_var = sen.distance_noise**2 * (self.left**2 + self.right**2) / base**2

    def steps(self, t0, t1):
        """(distance, turn, dt, still, wheel turn, its variance) per encoder interval or part of
        one, from t0 to t1 (ns)."""
        k = int(np.searchsorted(self.t, t0, side="right"))
        a = t0
        while a < t1 and k < len(self.t):
            b = min(t1, self.t[k])
            span = self.t[k] - self.t[k - 1]
            frac = (b - a) / span if span > 0 else 0.0
            yield (self.dist[k] * frac, self.turn(a, b), (b - a) * 1e-9, bool(self.still[k]),
                   self.wheel_turn[k] * frac, self.wheel_var[k] * frac)
            a = b
            k += 1


class Motion:
    """Planar motion between two frames in the first one's body frame, its covariance, its
    derivative with respect to a constant gyro bias, the gyro's mean rate while still, and the
    wheels' turn, distance and the turn's variance while moving."""

    def __init__(self, odo, sen, t0, t1):
        p = np.zeros(2)
        th = 0.0
        moving = 0.0
        jb = np.zeros(3)
        cov = np.zeros((3, 3))
        still_turn = 0.0
        self.still_s = 0.0
        self.wheel = np.zeros(3)  # turn, distance, the turn's variance
        for d, turn, dt, still, wturn, wvar in odo.steps(t0, t1):
            if still:
                still_turn += turn
                self.still_s += dt
                continue
            mid = th + 0.5 * turn
            c, s = math.cos(mid), math.sin(mid)
            dmid_db = -(moving + 0.5 * dt)
            jb[0] -= d * s * dmid_db
            jb[1] += d * c * dmid_db
            f = np.array([[1.0, 0.0, -d * s], [0.0, 1.0, d * c], [0.0, 0.0, 1.0]])
            g = np.array([-0.5 * d * s, 0.5 * d * c, 1.0])
            u = np.array([c, s, 0.0])
            turn_var = sen.density**2 * dt + (sen.gyro_scale_sd * turn) ** 2
            cov = (f @ cov @ f.T + np.outer(g, g) * turn_var +
                   np.outer(u, u) * (sen.distance_noise * d) ** 2)
            p += d * np.array([c, s])
            th += turn
            moving += dt
            self.wheel += (wturn, d, wvar)
        jb[2] = -moving
        self.delta = np.array([p[0], p[1], th])
        self.jb = jb
        self.info = np.linalg.inv(cov + np.diag([1e-8, 1e-8, 1e-10]))
        self.dt = (t1 - t0) * 1e-9
        self.still_rate = still_turn / self.still_s if self.still_s > 0 else 0.0


def compose(pose, delta):
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.array([pose[0] + c * delta[0] - s * delta[1], pose[1] + s * delta[0] + c * delta[1],
                     wrap(pose[2] + delta[2])])


def inverse(delta):
    c, s = math.cos(delta[2]), math.sin(delta[2])
    return np.array([-c * delta[0] - s * delta[1], s * delta[0] - c * delta[1], -delta[2]])


def ray_of(cam, pose, u, v):
    """Pixel (u, v)'s ray from a planar body pose: camera centre and unit direction (world)."""
    ray = cam.R_bc @ np.array([(u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0])
    c, s = math.cos(pose[2]), math.sin(pose[2])
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    centre = np.array([pose[0], pose[1], 0.0]) + rot @ cam.t_bc
    d = rot @ ray
    return centre, d / np.linalg.norm(d)


def triangulate(rays):
    """The point nearest all rays (least squares), or DR_DEPTH_M along the first ray when they
    are nearly parallel or meet behind one of them."""
    a = np.zeros((3, 3))
    b = np.zeros(3)
    for c, d in rays:
        m = np.eye(3) - np.outer(d, d)
        a += m
        b += m @ c
    if np.linalg.cond(a) < 1e4:
        p = np.linalg.solve(a, b)
        if all(0.2 < (p - c) @ d < 20.0 for c, d in rays):
            return p
    c, d = rays[0]
    return c + DR_DEPTH_M * d


def frames_of(feats, t_lo, t_hi):
    """[(t_ns, [(track id, u, v)])] for the frames within the encoder samples."""
    out = []
    i = 0
    while i < len(feats):
        t = feats[i, 0]
        obs = []
        while i < len(feats) and feats[i, 0] == t:
            obs.append((int(feats[i, 1]), feats[i, 2], feats[i, 3]))
            i += 1
        if t_lo < t <= t_hi:
            out.append((t, obs))
    return out


class FullSlam:
    """Keyframe i's unknowns are x, y, yaw, bias at 4i..4i+3; landmarks follow, 3 each; with the
    wheels' heading, their heading scale and drift per metre last."""

    def __init__(self, sen, odo, frames, truth, landmarks, start_t, start="truth", wheel=False):
        self.sen = sen
        self.times = [start_t] + [t for t, _ in frames]
        self.motions = [Motion(odo, sen, a, b) for a, b in zip(self.times[:-1], self.times[1:])]
        n = len(self.times)
        self.x = np.zeros(4 * n)
        # The gauge is the first frame's pose, held at the truth: errors are relative to it, as
        # cleanslam-eval --align none measures them.
        for i, t in enumerate(self.times):
            if start == "truth" or i == 1:
                self.x[4 * i:4 * i + 3] = truth.at(t * 1e-9)
        if start == "dr":
            self.x[:3] = compose(self.x[4:7], inverse(self.motions[0].delta))
            for i in range(2, n):
                self.x[4 * i:4 * i + 3] = compose(self.x[4 * i - 4:4 * i - 1],
                                                  self.motions[i - 1].delta)
        self.anchor = self.x[4:7].copy()
        obs = [(i + 1, tid, u, v) for i, (_, o) in enumerate(frames) for tid, u, v in o]
        ids = sorted({tid for _, tid, _, _ in obs if tid in landmarks})
        self.ids = ids
        col = {tid: 4 * n + 3 * q for q, tid in enumerate(ids)}
        if start == "truth":
            start_lm = {t: landmarks[t] for t in ids}
        else:
            rays = {}
            for i, tid, u, v in obs:
                if tid in col:
                    rays.setdefault(tid, []).append(ray_of(sen.cam, self.x[4 * i:4 * i + 3], u, v))
            start_lm = {tid: triangulate(r) for tid, r in rays.items()}
        self.x = np.concatenate([self.x, np.concatenate([start_lm[t] for t in ids]) if ids else []])
        self.lm_prior = self.x[4 * n:].copy()
        self.wheel_col = len(self.x) if wheel else None
        if wheel:
            if sen.wheel_base <= 0.0:
                raise ValueError("sensors.yaml: 'wheel_base' must be a positive number for "
                                 "--wheel-heading")
            self.x = np.concatenate([self.x, [0.0, 0.0]])
        self.n = n
        kept = [o for o in obs if o[1] in col]
        self.obs_kf = np.array([o[0] for o in kept], dtype=int)
        self.obs_col = np.array([col[o[1]] for o in kept], dtype=int)
        self.obs_uv = np.array([[o[2], o[3]] for o in kept]).reshape(-1, 2)
        self.dropped = len(obs) - len(kept)

    def residual_blocks(self, x):
        """[(columns per block (m, k), jacobians (m, r, k), residuals (m, r), weights (m, r, r))]
        and the rest of the cost: the robust loss beyond the Huber threshold and the observations
        predicted behind the camera."""
        sen, n = self.sen, self.n
        pose = x[:4 * n].reshape(n, 4)
        out = [([4 + np.arange(3)[None]], [np.eye(3)[None]], (pose[1, :3] - self.anchor)[None],
                (np.eye(3) * 1e8)[None]),
               ([np.array([[3]])], [np.ones((1, 1, 1))], pose[:1, 3:4],
                np.full((1, 1, 1), 1.0 / sen.bias_sd**2))]
        m = len(self.motions)
        if m:
            i, j = np.arange(m), np.arange(1, m + 1)
            delta = np.array([mo.delta for mo in self.motions])
            jb = np.array([mo.jb for mo in self.motions])
            info = np.array([mo.info for mo in self.motions])
            pi, pj, b = pose[i], pose[j], pose[i, 3]
            c, s = np.cos(pi[:, 2]), np.sin(pi[:, 2])
            dx, dy = pj[:, 0] - pi[:, 0], pj[:, 1] - pi[:, 1]
            rx, ry = c * dx + s * dy, -s * dx + c * dy
            r = np.stack([rx - delta[:, 0] - jb[:, 0] * b, ry - delta[:, 1] - jb[:, 1] * b,
                          wrap(pj[:, 2] - pi[:, 2] - delta[:, 2] - jb[:, 2] * b)], 1)
            z, o = np.zeros(m), np.ones(m)
            ji = np.stack([np.stack([-c, -s, ry], 1), np.stack([s, -c, -rx], 1),
                           np.stack([z, z, -o], 1)], 1)
            jj = np.stack([np.stack([c, s, z], 1), np.stack([-s, c, z], 1), np.stack([z, z, o], 1)],
                          1)
            a3 = np.arange(3)
            out.append(([4 * i[:, None] + a3, 4 * j[:, None] + a3, 4 * i[:, None] + 3],
                        [ji, jj, -jb[:, :, None]], r, info))
            walk = np.array([mo.dt for mo in self.motions]) * max(sen.bias_walk, 1e-6) ** 2
            out.append(([4 * i[:, None] + 3, 4 * j[:, None] + 3],
                        [-np.ones((m, 1, 1)), np.ones((m, 1, 1))],
                        (pose[j, 3] - pose[i, 3])[:, None],
                        (1.0 / walk)[:, None, None]))
            st = np.array([q for q in range(m) if self.motions[q].still_s >= STILL_MIN_S],
                          dtype=int)
            if len(st):
                rate = np.array([self.motions[q].still_rate for q in st])
                w = np.array([self.motions[q].still_s for q in st]) / sen.density**2
                out.append(([4 * st[:, None] + 3], [np.ones((len(st), 1, 1))],
                            (pose[st, 3] - rate)[:, None], w[:, None, None]))
        extra = 0.0
        if len(self.obs_kf):
            block, extra = self.pixel_block(pose, x)
            out.append(block)
        if self.ids:
            k = len(self.ids)
            cols = 4 * n + 3 * np.arange(k)[:, None] + np.arange(3)
            out.append(([cols], [np.broadcast_to(np.eye(3), (k, 3, 3))],
                        (x[4 * n:4 * n + 3 * k] - self.lm_prior).reshape(k, 3),
                        np.broadcast_to(np.eye(3) / LANDMARK_PRIOR_M**2, (k, 3, 3))))
        if self.wheel_col is not None:
            out.extend(self.wheel_blocks(pose, x))
        return out, extra

    def wheel_blocks(self, pose, x):
        """The wheels' turn between frames, theta = (1 + s) w - c d, and the priors of s and c."""
        wc = self.wheel_col
        s_, c_ = x[wc], x[wc + 1]
        prior = ([np.array([[wc, wc + 1]])], [np.eye(2)[None]], x[None, wc:wc + 2],
                 np.diag([1.0 / WHEEL_SCALE_SD**2, 1.0 / WHEEL_DRIFT_SD**2])[None])
        moving = [q for q, mo in enumerate(self.motions) if mo.wheel[2] > 0.0]
        if not moving:
            return [prior]
        q = np.array(moving, dtype=int)
        wheel = np.array([self.motions[k].wheel for k in moving])
        i, j = q, q + 1
        r = wrap(pose[j, 2] - pose[i, 2] - (1.0 + s_) * wheel[:, 0] + c_ * wheel[:, 1])
        m = len(q)
        one = np.ones((m, 1, 1))
        return [prior,
                ([4 * i[:, None] + 2, 4 * j[:, None] + 2, np.broadcast_to([wc, wc + 1], (m, 2))],
                 [-one, one, np.stack([-wheel[:, 0], wheel[:, 1]], 1)[:, None, :]], r[:, None],
                 (1.0 / wheel[:, 2])[:, None, None])]

    def pixel_block(self, pose, x):
        cam = self.sen.cam
        p = pose[self.obs_kf]
        lm = x[self.obs_col[:, None] + np.arange(3)]
        c, s = np.cos(p[:, 2]), np.sin(p[:, 2])
        rx, ry = lm[:, 0] - p[:, 0], lm[:, 1] - p[:, 1]
        pb = np.stack([c * rx + s * ry, -s * rx + c * ry, lm[:, 2]], 1)
        pc = (pb - cam.t_bc) @ cam.R_bc
        ok = pc[:, 2] > 0.05
        zc = np.where(ok, pc[:, 2], 1.0)
        uv = np.stack([cam.fx * pc[:, 0] / zc + cam.cx, cam.fy * pc[:, 1] / zc + cam.cy], 1)
        r = (uv - self.obs_uv) * ok[:, None]
        m = len(p)
        z = np.zeros(m)
        duv = np.stack([np.stack([cam.fx / zc, z, -cam.fx * pc[:, 0] / zc**2], 1),
                        np.stack([z, cam.fy / zc, -cam.fy * pc[:, 1] / zc**2], 1)], 1) @ cam.R_bc.T
        dpose = np.stack([np.stack([-c, -s, pb[:, 1]], 1), np.stack([s, -c, -pb[:, 0]], 1),
                          np.stack([z, z, z], 1)], 1)
        dlm = np.stack([np.stack([c, s, z], 1), np.stack([-s, c, z], 1),
                        np.stack([z, z, np.ones(m)], 1)], 1)
        e = np.sqrt((r * r).sum(1)) / cam.noise
        out = (e > HUBER) & ok
        w = np.where(out, HUBER / np.maximum(e, 1e-12), 1.0) * ok
        # Huber: w e^2 = H e; the loss is 2 H e - H^2, whose gradient the weights give
        extra = BEHIND_COST * float((~ok).sum()) + float((HUBER * e[out] - HUBER * HUBER).sum())
        a3 = np.arange(3)
        weight = np.eye(2)[None] * (w / cam.noise**2)[:, None, None]
        return ([4 * self.obs_kf[:, None] + a3, self.obs_col[:, None] + a3],
                [duv @ dpose, duv @ dlm], r, weight), extra

    def cost(self, x, system=False):
        blocks, total = self.residual_blocks(x)
        size = len(x)
        h = np.zeros((size, size)) if system else None
        g = np.zeros(size) if system else None
        for cols, jacs, r, w in blocks:
            wr = np.einsum("mab,mb->ma", w, r)
            total += float((r * wr).sum())
            if not system:
                continue
            for ca, ja in zip(cols, jacs):
                np.add.at(g, ca, np.einsum("mra,mr->ma", ja, wr))
                jw = np.einsum("mra,mrs->mas", ja, w)
                for cb, jb in zip(cols, jacs):
                    np.add.at(h, (ca[:, :, None], cb[:, None, :]),
                              np.einsum("mas,msb->mab", jw, jb))
        return total, h, g

    def solve(self, iterations, progress=None):
        lam = 1e-3
        cost, h, g = self.cost(self.x, True)
        done = 0
        for done in range(1, iterations + 1):
            for _ in range(10):
                try:
                    step = -block_solve(h + lam * np.diag(np.diag(h) + 1e-9), g, 4 * self.n)
                except np.linalg.LinAlgError:
                    lam *= 10.0
                    continue
                trial = self.x + step
                trial[2:4 * self.n:4] = wrap(trial[2:4 * self.n:4])
                new, _, _ = self.cost(trial)
                if new < cost:
                    break
                lam *= 10.0
            else:
                return cost, done
            self.x = trial
            lam = max(lam / 5.0, 1e-9)
            old = cost
            cost, h, g = self.cost(self.x, True)
            if progress is not None:
                progress(done, cost)
            if old - cost < 1e-9 * old:
                break
        return cost, done


def block_solve(a, b, npose):
    """a x = b where a's first npose unknowns (4 per keyframe) couple only neighbouring keyframes:
    block-tridiagonal elimination of the poses, then the landmarks' Schur complement."""
    m = npose // 4
    rhs = np.concatenate([b[:npose, None], a[:npose, npose:]], 1)
    diag = [a[4 * i:4 * i + 4, 4 * i:4 * i + 4].copy() for i in range(m)]
    right = [rhs[4 * i:4 * i + 4].copy() for i in range(m)]
    upper = [a[4 * i:4 * i + 4, 4 * i + 4:4 * i + 8] for i in range(m - 1)]
    for i in range(1, m):
        f = np.linalg.solve(diag[i - 1], upper[i - 1]).T
        diag[i] = diag[i] - f @ upper[i - 1]
        right[i] = right[i] - f @ right[i - 1]
    sol = [None] * m
    sol[-1] = np.linalg.solve(diag[-1], right[-1])
    for i in range(m - 2, -1, -1):
        sol[i] = np.linalg.solve(diag[i], right[i] - upper[i] @ sol[i + 1])
    inv = np.concatenate(sol, 0)
    if len(b) == npose:
        return inv[:, 0]
    coupling = a[:npose, npose:]
    schur = a[npose:, npose:] - coupling.T @ inv[:, 1:]
    lm = np.linalg.solve(schur, b[npose:] - coupling.T @ inv[:, 0])
    return np.concatenate([inv[:, 0] - inv[:, 1:] @ lm, lm])


def filtering_variances(fs):
    """Per frame, the position variance (trace) given only the data up to that frame: the
    information of (newest keyframe, landmarks) swept forward in time with the older keyframes
    marginalized, linearized at the smoothed solution. A bias-only factor (standing still) counts
    from the next keyframe on, when its interval has ended."""
    n = fs.n
    nl = len(fs.x) - 4 * n
    by_time = [[] for _ in range(n + 1)]
    blocks, _ = fs.residual_blocks(fs.x)
    for cols, jacs, _, w in blocks:
        for m in range(len(w)):
            c = np.concatenate([ca[m] for ca in cols])
            j = np.concatenate([ja[m] for ja in jacs], axis=1)
            kf = c[c < 4 * n] // 4
            t = int(kf.max()) if len(kf) else 0
            if len(c) == 1 and c[0] < 4 * n and c[0] % 4 == 3:
                t += 1
            by_time[min(t, n)].append((c, j.T @ w[m] @ j))
    size = 8 + nl
    info = np.zeros((size, size))
    var = []
    for k in range(n + 1):
        for c, blk in by_time[k]:
            loc = np.where(c >= 4 * n, 8 + c - 4 * n, c - 4 * (k - 1))
            info[np.ix_(loc, loc)] += blk
        if k == n:
            break
        keep = np.r_[4:size]
        if k > 0:
            prev = info[:4, :4] + np.eye(4) * 1e-12
            info[np.ix_(keep, keep)] -= info[np.ix_(keep, range(4))] @ np.linalg.solve(
                prev, info[np.ix_(range(4), keep)])
        if k >= 1:
            cov = np.linalg.inv(info[np.ix_(keep, keep)] + np.eye(len(keep)) * 1e-12)
            var.append(cov[0, 0] + cov[1, 1])
        shifted = np.zeros((size, size))
        kept = np.r_[4:8, 8:size]
        shifted[np.ix_(np.r_[0:4, 8:size], np.r_[0:4, 8:size])] = info[np.ix_(kept, kept)]
        info = shifted
    return np.array(var)


def smoothing_variances(fs):
    """Per frame, the position variance (trace) given all the data."""
    _, h, _ = fs.cost(fs.x, True)
    cov = np.linalg.inv(h + np.eye(len(h)) * 1e-12)
    return np.array([cov[4 * i, 4 * i] + cov[4 * i + 1, 4 * i + 1] for i in range(1, fs.n)])


def rms_sd(variances):
    return math.sqrt(max(float(np.mean(variances)), 0.0)) if len(variances) else 0.0


def problem(dataset, start="truth", wheel=False):
    """The dataset's full-SLAM problem, unsolved, started from the truth or from dead reckoning,
    and the true landmarks by track id."""
    sen = kmb.Sensors(dataset)
    if any(k != 0.0 for k in (sen.cam.k1, sen.cam.k2, sen.cam.p1, sen.cam.p2)):
        raise ValueError(f"{dataset}/sensors.yaml: 'distortion' must be zeros (this tool's camera "
                         "model is a pinhole)")
    odo = Odometry(dataset, sen)
    feats = kmb.load_csv(os.path.join(dataset, "features.csv"), 4)
    lms = kmb.load_csv(os.path.join(dataset, "sim_landmarks.csv"), 4)
    truth = trajectory.PlanarTruth(
        trajectory.read_groundtruth(os.path.join(dataset, "groundtruth.csv")))
    frames = frames_of(feats, odo.t[0], odo.t[-1])
    if not frames:
        raise ValueError(f"{dataset}/features.csv: no frame within the encoder samples")
    landmarks = {int(r[0]): r[1:4].astype(float) for r in lms}
    return FullSlam(sen, odo, frames, truth, landmarks, odo.t[0], start, wheel), landmarks


def smooth(dataset, iterations=200, progress=None, start="truth", wheel=False):
    """[(t_s, x, y, yaw)] at the frames with features, the landmarks' mean planar error, the number
    of observations of unknown landmarks, LM iterations, and the RMS position standard deviations
    at the frames given all the data (smoothing) and given the data up to each (filtering), from
    the information at the solution."""
    fs, landmarks = problem(dataset, start, wheel)
    _, done = fs.solve(iterations, progress)
    n = fs.n
    spread = (rms_sd(smoothing_variances(fs)), rms_sd(filtering_variances(fs)))
    pose = fs.x[:4 * n].reshape(n, 4)
    poses = [(t * 1e-9, p[0], p[1], p[2]) for t, p in zip(fs.times[1:], pose[1:])]
    lm = fs.x[4 * n:4 * n + 3 * len(fs.ids)].reshape(-1, 3)
    err = [float(np.hypot(*(lm[q, :2] - landmarks[t][:2]))) for q, t in enumerate(fs.ids)]
    return poses, (float(np.mean(err)) if err else 0.0), fs.dropped, done, spread


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset")
    ap.add_argument("run")
    ap.add_argument("--iterations", type=int, default=200)
    ap.add_argument("--start", choices=["truth", "dr"], default="truth",
                    help="start from the truth (the bound) or from dead reckoning (how far a "
                    "local solver gets without knowing the basin)")
    ap.add_argument("--out", help="write the smoothed poses here (TUM)")
    ap.add_argument("--wheel-heading", action="store_true",
                    help="the wheels' turn as a second measurement of the heading change")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    if a.iterations < 1:
        print("full_slam_bound: --iterations must be at least 1", file=sys.stderr)
        return 2

    def progress(k, cost):
        print(f"full_slam_bound: iteration {k}, cost {cost:.1f}", file=sys.stderr)

    try:
        poses, lm_err, dropped, done, spread = smooth(
            a.dataset, a.iterations, None if a.json else progress, a.start, a.wheel_heading)
        dr = sighting_bound.bound(a.dataset, a.run)
    except (OSError, ValueError) as e:
        print(f"full_slam_bound: {e}", file=sys.stderr)
        return 1
    r = {"frames": len(poses), "iterations": done, "dr_ate_m": dr["dr_ate_m"],
         "full_slam_ate_m": kmb.world_ate(a.dataset, poses), "smoothing_sd_m": spread[0],
         "filtering_sd_m": spread[1],
         "landmark_error_m": lm_err,
         "observations_without_landmark": dropped}
    if a.out:
        kmb.write_tum(a.out, poses)
    if a.json:
        print(json.dumps(r))
    else:
        print(f"{r['frames']} frames with features: DR ATE {r['dr_ate_m']:.3f} m, full SLAM "
              f"smoothed from {'the truth' if a.start == 'truth' else 'dead reckoning'} "
              f"{r['full_slam_ate_m']:.3f} m; position std. dev. given all the data "
              f"{r['smoothing_sd_m']:.3f} m, given the data so far {r['filtering_sd_m']:.3f} m "
              f"(landmarks {r['landmark_error_m']:.3f} m off)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
