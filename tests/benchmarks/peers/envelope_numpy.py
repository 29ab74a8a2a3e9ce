#!/usr/bin/env python3
"""Peer of the resonance envelope (docs/benchmarks.md "Resonance envelope against numpy"): a
straightforward vectorised numpy modal superposition of the same cases as
inputs/beam/axle_train.yaml with beam.modes = 20: a simply supported beam in sine modes with
modal damping, the generic articulated train as moving forces, classical RK4 at a fixed step
with every speed of a train advanced together (arrays speeds x modes), the peak midspan
acceleration w_tt(L/2) over the steps (from the equation of motion) until the last axle has left.

Usage: envelope_numpy.py --coach-lengths 14 15 ... --speeds V0 V1 COUNT --dt DT [--modes 20] [--csv OUT]
Prints the wall time and writes (coach_length, speed, peak) rows.
"""
import argparse
import csv
import time

import numpy as np

L, EI, RHOA, ZETA = 25.0, 3.5e10 * 1.3901, 2500 * 7.3432, 0.02
COACHES, AXLE_SPACING, P = 10, 2.5, 1.7e5


def offsets(D):
    return np.array([b * D + e for b in range(COACHES + 3) for e in (0.0, AXLE_SPACING)])


def envelope(D, speeds, dt, n):
    k = np.arange(1, n + 1) * np.pi / L                      # wave numbers (n,)
    w = k * k * np.sqrt(EI / RHOA)                           # omega_i
    m = RHOA * L / 2.0                                       # modal mass
    phi_mid = np.sin(k * L / 2.0)
    e = offsets(D)                                           # (A,)
    v = np.asarray(speeds)[:, None]                          # (S, 1)
    t_end = (L + e[-1]) / v[:, 0]                            # (S,)

    def force(t):
        x = v * t - e[None, :]                               # (S, A)
        on = (x >= 0.0) & (x <= L)
        s = np.sin(x[:, :, None] * k[None, None, :])         # (S, A, n)
        return -(P / m) * np.einsum("sa,san->sn", on.astype(float), s)

    def acc(t, q, p):
        return force(t) - 2.0 * ZETA * w * p - w * w * q

    q = np.zeros((len(speeds), n))
    p = np.zeros_like(q)
    peak = np.zeros(len(speeds))
    steps = int(np.ceil(t_end.max() / dt))
    for j in range(steps):
        t = j * dt
        k1q, k1p = p, acc(t, q, p)
        k2q, k2p = p + 0.5 * dt * k1p, acc(t + 0.5 * dt, q + 0.5 * dt * k1q, p + 0.5 * dt * k1p)
        k3q, k3p = p + 0.5 * dt * k2p, acc(t + 0.5 * dt, q + 0.5 * dt * k2q, p + 0.5 * dt * k2p)
        k4q, k4p = p + dt * k3p, acc(t + dt, q + dt * k3q, p + dt * k3p)
        q = q + dt / 6.0 * (k1q + 2 * k2q + 2 * k3q + k4q)
        p = p + dt / 6.0 * (k1p + 2 * k2p + 2 * k3p + k4p)
        a_mid = acc(t + dt, q, p) @ phi_mid
        live = (t + dt) <= t_end + 1e-12
        peak = np.where(live, np.maximum(peak, np.abs(a_mid)), peak)
    return peak


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--coach-lengths", type=float, nargs="+", required=True)
    ap.add_argument("--speeds", type=float, nargs=3, required=True, metavar=("V0", "V1", "COUNT"))
    ap.add_argument("--dt", type=float, required=True)
    ap.add_argument("--modes", type=int, default=20)
    ap.add_argument("--csv", default=None)
    a = ap.parse_args()
    speeds = np.linspace(a.speeds[0], a.speeds[1], int(a.speeds[2]))
    rows, start = [], time.perf_counter()
    for D in a.coach_lengths:
        for v, y in zip(speeds, envelope(D, speeds, a.dt, a.modes)):
            rows.append((D, v, y))
    wall = time.perf_counter() - start
    print(f"numpy envelope: {len(a.coach_lengths)} train(s) x {len(speeds)} speeds, {a.modes} modes, dt = {a.dt} s: "
          f"{wall:.2f} s wall")
    if a.csv:
        with open(a.csv, "w", newline="") as fh:
            csv.writer(fh).writerows([("coach_length", "speed", "peak")] + rows)


if __name__ == "__main__":
    main()
