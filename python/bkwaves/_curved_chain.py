"""Planar and gently curved fronts on the square lattice, reduced to chains.

A planar front whose normal is the lattice direction (q, p) (integers without a common
factor, dx = dy) reaches every block on a line m = q i + p j at the same time, so the
lattice reduces exactly to a chain in m with spacing h = dx/sqrt(p^2 + q^2) along the
normal, in which each block is coupled to m +- q (its x neighbours) and m +- p (its y
neighbours), all with the spring 1/dx^2: (1, 0) is the chain at dx, (1, 1) the chain at
dx/sqrt(2) (docs/lattice.md).

A front of curvature kappa reaches the blocks beside a block later than the block itself
(arrival time T = (n + kappa s^2/2)/c, n the normal and s the tangential coordinate). To
first order in kappa a neighbour's displacement is the planar one delayed, U(t - Delta) =
U(t) - Delta U_t(t): a neighbour at tangential offset s enters with the value u - delta u_t,
delta = kappa s^2/(2c) (the x neighbours sit at s = p dx/L, the y neighbours at q dx/L,
L = sqrt(p^2 + q^2); docs/theory.md, section 7). Along an axis the y neighbours are on
the block's own line (offset 0), so their delay is an extra drag -(kappa/c) u_t.

This module integrates those chains on its own (numpy, classical RK4, each slip located
by bisection of the step), independently of the Rust engine. Blocks slip once and keep
sliding: the front is supersonic, so nothing behind it reaches the stuck blocks ahead,
and re-sticking behind cannot change its speed.
"""

from __future__ import annotations

import math

import numpy as np


def front_speed(
    u_plus: float,
    gamma: float,
    dx: float,
    direction: tuple[int, int] = (1, 0),
    *,
    kappa: float = 0.0,
    c_ref: float | None = None,
    drag: float = 0.0,
    blocks: int | None = None,
    steps_per_slip: int = 40,
) -> tuple[float, float]:
    """The steady speed of a front on the lattice (dx = dy, v = 0, uniform u_+ ahead)
    whose normal is the lattice direction ``direction`` = (q, p), with curvature
    ``kappa`` to first order (delays computed with the speed ``c_ref``), plus an extra
    drag ``drag`` u_t on every block.

    Returns (c, change): c, the speed along the normal, from a line through the slip
    times of the middle third of the chain against their positions, and the change of c
    between the halves of that window (the steadiness of the measurement).
    """
    q, p = (int(abs(direction[0])), int(abs(direction[1])))
    if math.gcd(q, p) != 1:
        raise ValueError(f"direction must be two integers without a common factor, got {direction}")
    ell = math.hypot(p, q)
    h = dx / ell
    c_ref = c_ref if c_ref is not None else 1.0
    # (offset in m, delay of that neighbour's value per unit of its velocity)
    couplings = [
        (q, kappa * (p * dx / ell) ** 2 / (2.0 * c_ref)),
        (p, kappa * (q * dx / ell) ** 2 / (2.0 * c_ref)),
    ]
    pad = max(q, p)
    n = int(blocks or 170 + 90 * pad)
    u = np.full(n, float(u_plus))
    v = np.zeros(n)
    sliding = np.zeros(n, bool)
    slip_time = np.full(n, np.nan)
    start = q + p + 2  # the first lines released at t = 0 start the front
    sliding[:start] = True
    slip_time[:start] = 0.0
    inv = 1.0 / (dx * dx)
    damp = 2.0 * gamma + drag
    last = n - 2 * pad - 2  # blocks beyond feel the chain's far end

    def lap(u, v):
        uu = np.concatenate([np.full(pad, u[0]), u, np.full(pad, u[-1])])
        vv = np.concatenate([np.zeros(pad), v, np.zeros(pad)])
        out = np.zeros(n)
        for off, delay in couplings:
            w = uu - delay * vv if delay else uu
            out += w[pad + off : pad + off + n] + w[pad - off : pad - off + n] - 2.0 * u
        return out * inv

    def accel(u, v):
        a = lap(u, v) - u - damp * v
        a[~sliding] = 0.0
        return a

    def velocity(v):
        return np.where(sliding, v, 0.0)

    def step(u, v, tau):
        k1u, k1v = velocity(v), accel(u, v)
        k2u = velocity(v + 0.5 * tau * k1v)
        k2v = accel(u + 0.5 * tau * k1u, v + 0.5 * tau * k1v)
        k3u = velocity(v + 0.5 * tau * k2v)
        k3v = accel(u + 0.5 * tau * k2u, v + 0.5 * tau * k2v)
        k4u = velocity(v + tau * k3v)
        k4v = accel(u + tau * k3u, v + tau * k3v)
        return (
            u + tau / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u),
            v + tau / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
        )

    def most_loaded(u, v):
        phi = u - lap(u, v)
        phi[sliding] = -np.inf
        phi[last:] = -np.inf
        k = int(np.argmax(phi))
        return phi[k], k

    dt = h / (1.3 * steps_per_slip)
    t = 0.0
    while not sliding[last - 1]:
        un, vn = step(u, v, dt)
        if most_loaded(un, vn)[0] < 1.0:
            u, v, t = un, vn, t + dt
            continue
        lo, hi = 0.0, dt
        for _ in range(44):
            mid = 0.5 * (lo + hi)
            if most_loaded(*step(u, v, mid))[0] >= 1.0:
                hi = mid
            else:
                lo = mid
        u, v = step(u, v, hi)
        t += hi
        k = most_loaded(u, v)[1]
        sliding[k] = True
        slip_time[k] = t
    idx = np.arange(last // 3, 2 * last // 3)
    x = idx * h
    ts = slip_time[idx]
    half = idx.size // 2
    c = 1.0 / np.polyfit(x, ts, 1)[0]
    c1 = 1.0 / np.polyfit(x[:half], ts[:half], 1)[0]
    c2 = 1.0 / np.polyfit(x[half:], ts[half:], 1)[0]
    return float(c), float(c2 - c1)
